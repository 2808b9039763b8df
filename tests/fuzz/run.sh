#!/usr/bin/env bash
# Runs every fuzz target of a PDT_BUILD_FUZZERS build twice: for SECONDS on
# its committed seed corpus (tests/fuzz/corpus/<target>/) plus a scratch
# corpus, then for EMPTY_SECONDS from an empty corpus, each run with the
# target's dictionary (tests/fuzz/fuzz_<target>.dict). Prints executions
# and coverage per run.
#
# Usage: tests/fuzz/run.sh BUILD_DIR SECONDS [WORK_DIR [EMPTY_SECONDS [extra libFuzzer args]]]
#   BUILD_DIR      a build configured with CC=clang -DPDT_BUILD_FUZZERS=ON
#   SECONDS        run time of each target on its seeds (0: no such run)
#   WORK_DIR       scratch corpora and crash artifacts (default BUILD_DIR/fuzz-work)
#   EMPTY_SECONDS  run time of each target from an empty corpus (default 0:
#                  none)
# Exits non-zero if a run finds a contract violation or a sanitizer report
# (the input is left in WORK_DIR/<target>/crash-* or WORK_DIR/<target>-empty/);
# the other targets still run.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
secs=$2
work=${3:-$build/fuzz-work}
empty_secs=${4:-0}
shift $(($# < 4 ? $# : 4))
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$here/ubsan.supp"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
status=0

# run NAME LABEL SECONDS CORPUS_DIR...: one libFuzzer run, its summary line.
run() {
    local name=$1 label=$2 time=$3 target=${1#fuzz_}
    shift 3
    local log="$work/$label.log"
    local limit=(-max_total_time="$time")
    if grep -qx "$target" "$here/open_findings.txt" 2>/dev/null; then
        # An open finding (open_findings.txt): its corpus only, no exploring.
        limit=(-runs=0)
        echo "$label: open finding (tests/fuzz/findings/), corpus only"
    fi
    # The option parser prints a message for every refused input.
    [ "$target" = options ] && limit+=(-close_fd_mask=3)
    mkdir -p "$work/$label"
    if ! "$build/tests/fuzz/$name" "${limit[@]}" -timeout=10 -rss_limit_mb=1024 \
        -print_final_stats=1 -dict="$here/$name.dict" -artifact_prefix="$work/$label/" \
        "${extra[@]}" "$@" >"$log" 2>&1; then
        echo "$label: FAILED (log $log)"
        grep -E "contract violated|runtime error|ERROR:" "$log" | head -5 || true
        status=1
        return
    fi
    local execs cov
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    cov=$(grep -Eo "cov: [0-9]+ ft: [0-9]+" "$log" | tail -1)
    echo "$label: $execs executions in $time s, $cov"
}

extra=("$@")
for bin in "$build"/tests/fuzz/fuzz_*; do
    [ -x "$bin" ] || continue
    name=$(basename "$bin")
    target=${name#fuzz_}
    mkdir -p "$here/corpus/$target"
    if ((secs > 0)); then
        run "$name" "$name" "$secs" "$work/$name" "$here/corpus/$target"
    fi
    if ((empty_secs > 0)); then
        # A fresh corpus each time: what the seeds would hide.
        rm -rf "$work/$name-empty-corpus"
        mkdir -p "$work/$name-empty-corpus"
        run "$name" "$name-empty" "$empty_secs" "$work/$name-empty-corpus"
    fi
done
exit $status
