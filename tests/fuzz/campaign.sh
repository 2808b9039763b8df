#!/usr/bin/env bash
# A long fuzzing campaign: runs each target of a PDT_BUILD_FUZZERS build
# until it has made QUOTA executions (restarting after a finding, whose
# input is kept), then prints executions, coverage and findings per target
# as a Markdown table for docs/fuzzing.md.
#
# Usage: tests/fuzz/campaign.sh BUILD_DIR WORK_DIR QUOTA [TARGET...]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
work=$2
quota=$3
shift 3
targets=("$@")
if ((${#targets[@]} == 0)); then
    for bin in "$build"/tests/fuzz/fuzz_*; do targets+=("$(basename "$bin")"); done
fi
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$here/ubsan.supp"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
echo "| target | executions | coverage (edges) | features | findings |"
echo "|---|---:|---:|---:|---|"
for name in "${targets[@]}"; do
    target=${name#fuzz_}
    mkdir -p "$work/$name/corpus" "$work/$name/artifacts"
    done_runs=0
    round=0
    while ((done_runs < quota)); do
        round=$((round + 1))
        log="$work/$name/round$round.log"
        "$build/tests/fuzz/$name" -runs=$((quota - done_runs)) -timeout=10 -rss_limit_mb=1024 \
            -print_final_stats=1 -artifact_prefix="$work/$name/artifacts/" \
            "$work/$name/corpus" "$here/corpus/$target" >"$log" 2>&1
        n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
        [ -n "$n" ] || n=$(grep -Eo "^#[0-9]+" "$log" | tail -1 | tr -d '#')
        done_runs=$((done_runs + ${n:-0}))
        ((round < 50)) || break
        [ "${n:-0}" -gt 0 ] || break
    done
    cov=$(grep -Eo "cov: [0-9]+ ft: [0-9]+" "$work/$name"/round*.log | tail -1 | awk '{print $2" | "$4}')
    found=$(find "$work/$name/artifacts" -type f | wc -l)
    echo "| $name | $done_runs | $cov | $found inputs ($((round - 1)) stops) |"
done
