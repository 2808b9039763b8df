#!/usr/bin/env bash
# Runs every fuzz target of a PDT_BUILD_FUZZERS build for a while, each on
# its committed seed corpus (tests/fuzz/corpus/<target>/) plus a scratch
# corpus, and prints executions and coverage per target.
#
# Usage: tests/fuzz/run.sh BUILD_DIR SECONDS [WORK_DIR [extra libFuzzer args]]
#   BUILD_DIR  a build configured with CC=clang -DPDT_BUILD_FUZZERS=ON
#   SECONDS    run time of each target
#   WORK_DIR   scratch corpora and crash artifacts (default BUILD_DIR/fuzz-work)
# Exits non-zero on the first target that finds a contract violation or a
# sanitizer report (the input is left in WORK_DIR/<target>/crash-*).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
secs=$2
work=${3:-$build/fuzz-work}
shift $(($# < 3 ? $# : 3))
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$here/ubsan.supp"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
status=0
for bin in "$build"/tests/fuzz/fuzz_*; do
    [ -x "$bin" ] || continue
    name=$(basename "$bin")
    target=${name#fuzz_}
    mkdir -p "$work/$name" "$here/corpus/$target"
    log="$work/$name.log"
    limit=(-max_total_time="$secs")
    if grep -qx "$target" "$here/open_findings.txt" 2>/dev/null; then
        # An open finding (open_findings.txt): its corpus only, no exploring.
        limit=(-runs=0)
        echo "$name: open finding (tests/fuzz/findings/), corpus only"
    fi
    # The option parser prints a message for every refused input.
    [ "$target" = options ] && limit+=(-close_fd_mask=3)
    if ! "$bin" "${limit[@]}" -timeout=10 -rss_limit_mb=1024 -print_final_stats=1 \
        -artifact_prefix="$work/$name/" "$@" "$work/$name" "$here/corpus/$target" >"$log" 2>&1; then
        echo "$name: FAILED (log $log)"
        grep -E "contract violated|runtime error|ERROR:" "$log" | head -5 || true
        status=1
        continue
    fi
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    cov=$(grep -Eo "cov: [0-9]+ ft: [0-9]+" "$log" | tail -1)
    echo "$name: $execs executions, $cov"
done
exit $status
