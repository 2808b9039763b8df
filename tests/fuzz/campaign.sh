#!/usr/bin/env bash
# A long fuzzing campaign: runs each target of a PDT_BUILD_FUZZERS build
# for QUOTA executions or SECONDS of run time, whichever ends first
# (restarting after a finding, whose input is kept), then prints
# executions, coverage and findings per target as a Markdown table for
# docs/fuzzing.md. Executions of earlier runs in WORK_DIR (run*.log) are
# added, so a campaign can be resumed.
#
# Usage: tests/fuzz/campaign.sh BUILD_DIR WORK_DIR QUOTA SECONDS [TARGET...]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
work=$2
quota=$3
secs=$4
shift 4
targets=("$@")
if ((${#targets[@]} == 0)); then
    for bin in "$build"/tests/fuzz/fuzz_*; do targets+=("$(basename "$bin")"); done
fi
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$here/ubsan.supp"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
executed() { # log file
    local n
    n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$1")
    [ -n "$n" ] || n=$(grep -Eo "^#[0-9]+" "$1" | tail -1 | tr -d '#')
    echo "${n:-0}"
}
echo "| target | executions | coverage (edges) | features | corpus | findings |"
echo "|---|---:|---:|---:|---:|---|"
for name in "${targets[@]}"; do
    target=${name#fuzz_}
    mkdir -p "$work/$name/corpus" "$work/$name/artifacts"
    done_runs=0
    for old in "$work/$name"/run*.log; do
        [ -e "$old" ] && done_runs=$((done_runs + $(executed "$old")))
    done
    start=$SECONDS
    k=0
    while ((done_runs < quota && SECONDS - start < secs)); do
        k=$((k + 1))
        log="$work/$name/run$(date +%s)-$k.log"
        "$build/tests/fuzz/$name" -runs=$((quota - done_runs)) \
            -max_total_time=$((secs - (SECONDS - start))) -timeout=10 -rss_limit_mb=2048 \
            -print_final_stats=1 -artifact_prefix="$work/$name/artifacts/" \
            "$work/$name/corpus" "$here/corpus/$target" >"$log" 2>&1
        rc=$?
        done_runs=$((done_runs + $(executed "$log")))
        ((rc != 0)) || break
    done
    last=$(ls -t "$work/$name"/run*.log | head -1)
    cov=$(grep -Eo "cov: [0-9]+ ft: [0-9]+ corp: [0-9]+" "$last" | tail -1 |
        awk '{print $2" | "$4" | "$6}')
    found=$(find "$work/$name/artifacts" -type f | wc -l)
    echo "| $name | $done_runs | $cov | $found |"
done
