#!/usr/bin/env bash
# The long fuzzing campaign (docs/fuzzing.md): each target of a
# PDT_BUILD_FUZZERS build from an empty corpus with its dictionary
# (tests/fuzz/fuzz_<target>.dict), one target at a time, one process, until
# it has made its quota of executions or run SECONDS, whichever ends first.
# A run that finds something is restarted on the corpus so far; the finding's
# input stays in WORK_DIR/<target>/artifacts/. fuzz_ident and fuzz_autotune
# run in their quick modes (FZ_IDENT_SMALL=1: records of at most 24 samples,
# smaller budgets; FZ_AUTOTUNE_SMALL=1: capacities of at most 31 samples,
# smaller budgets) and without libFuzzer's entropic schedule (-entropic=0):
# a whole search touches so many features that the schedule's bookkeeping
# per feature took most of each run (docs/fuzzing.md).
# The runs of an earlier call in WORK_DIR count (run*.log), so a campaign
# can be resumed (a target given 0 s only prints its line of the table). Prints a Markdown table (also WORK_DIR/campaign.md):
# executions, run time, rate, coverage and findings per target.
#
# Usage: tests/fuzz/campaign.sh BUILD_DIR WORK_DIR SECONDS [TARGET[:QUOTA[:SECONDS]]...]
#   SECONDS  the most run time of each target (a target's own after it)
#   TARGET   ident, autotune, ... (default: every target, with the quotas
#            below: 10^7 executions each, 4 x 10^7 of the option parser,
#            10^8 in all)
# Runs at nice 10: the machine is shared.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
work=$2
secs=$3
shift 3
declare -A quota=([ident]=10000000 [autotune]=10000000 [tune]=10000000 [cost]=10000000
    [reduce]=10000000 [csv]=10000000 [options]=40000000)
plan=("$@")
((${#plan[@]} > 0)) || plan=(ident autotune tune cost reduce csv options)
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$here/ubsan.supp"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export FZ_IDENT_SMALL=1 FZ_AUTOTUNE_SMALL=1

# sum_logs DIR PATTERN: the total over DIR/run*.log of a figure's last value
# in each log.
sum_logs() {
    local total=0 n log
    for log in "$1"/run*.log; do
        [ -e "$log" ] || continue
        n=$(grep -Eo "$2" "$log" | tail -1 | grep -Eo "[0-9]+$")
        total=$((total + ${n:-0}))
    done
    echo "$total"
}
executed() { sum_logs "$1" "(number_of_executed_units: *|^#)[0-9]+"; }
# seconds_run DIR: the run time of DIR/run<start>-<k>.log, from the start
# in its name to its last write (a run that found something prints no
# "Done ... in S second(s)").
seconds_run() {
    local total=0 log start
    for log in "$1"/run*.log; do
        [ -e "$log" ] || continue
        start=${log##*/run}
        start=${start%%-*}
        total=$((total + $(stat -c %Y "$log") - start))
    done
    echo "$total"
}

table=$work/campaign.md
mkdir -p "$work"
# The commits the campaign ran at, one a line (a resumed campaign may add one).
head=$(git -C "$here" rev-parse --short HEAD)
[ "$(tail -1 "$work/commit" 2>/dev/null)" = "$head" ] || echo "$head" >>"$work/commit"
{
    echo "| target | executions | run time (s) | executions/s | coverage (cov) | features (ft) | corpus | findings |"
    echo "|---|---:|---:|---:|---:|---:|---:|---|"
} >"$table"
cat "$table"
for item in "${plan[@]}"; do
    IFS=: read -r target want cap <<<"$item"
    want=${want:-${quota[$target]:-10000000}}
    cap=${cap:-$secs}
    name=fuzz_$target
    dir=$work/$name
    mkdir -p "$dir/corpus" "$dir/artifacts"
    start=$SECONDS
    k=0
    while (($(executed "$dir") < want && SECONDS - start < cap)); do
        k=$((k + 1))
        opts=()
        [ "$target" = options ] && opts+=(-close_fd_mask=3)
        [ "$target" = ident ] || [ "$target" = autotune ] && opts+=(-entropic=0)
        nice -n 10 "$build/tests/fuzz/$name" -runs=$((want - $(executed "$dir"))) \
            -max_total_time=$((cap - (SECONDS - start))) -timeout=10 -rss_limit_mb=2048 \
            -dict="$here/$name.dict" -print_final_stats=1 -artifact_prefix="$dir/artifacts/" \
            "${opts[@]}" "$dir/corpus" >"$dir/run$(date +%s)-$k.log" 2>&1 || continue
    done
    runs=$(executed "$dir")
    time=$(seconds_run "$dir")
    rate=$((runs / (time > 0 ? time : 1)))
    last=$(ls -t "$dir"/run*.log 2>/dev/null | head -1)
    cov=$(grep -Eo "cov: [0-9]+ ft: [0-9]+ corp: [0-9]+" "$last" 2>/dev/null | tail -1 |
        awk '{print $2" | "$4" | "$6}')
    found=$(find "$dir/artifacts" -type f | wc -l)
    found_text=none
    ((found == 0)) || found_text="$found inputs (kept in WORK_DIR/$name/artifacts)"
    echo "| \`$name\` | $runs | $time | $rate | ${cov:-? | ? | ?} | $found_text |" | tee -a "$table"
done
