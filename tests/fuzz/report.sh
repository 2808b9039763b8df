#!/usr/bin/env bash
# Writes docs/reports/fuzzing.md from a campaign's WORK_DIR
# (tests/fuzz/campaign.sh) and a check's WORK_DIR (tests/fuzz/check.sh),
# the prose from tests/fuzz/report.md.in beside this script.
#
# Usage: tests/fuzz/report.sh CAMPAIGN_DIR CHECK_DIR [OUT]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
camp=$1
check=$2
out=${3:-$here/../../docs/reports/fuzzing.md}
declare -A quota=([ident]=10000000 [autotune]=10000000 [tune]=10000000 [cost]=10000000
    [reduce]=10000000 [csv]=10000000 [options]=40000000)

cpu=$(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -1)
machine="$cpu, $(nproc) cores, $(uname -sr)"
campaign_table=$(cat "$camp/campaign.md")
rows=$(grep '^| `fuzz_' "$camp/campaign.md")
total=$(awk -F'|' '{s += $3} END {print s}' <<<"$rows")
seconds=$(awk -F'|' '{s += $4} END {print s}' <<<"$rows")

# The quotas' time at the measured rates.
quota_table="| target | quota | executions/s | time for the quota (h) |
|---|---:|---:|---:|"
hours_all=0
while IFS='|' read -r _ name _ _ rate _; do
    t=$(tr -d ' `' <<<"$name")
    t=${t#fuzz_}
    rate=$(tr -d ' ' <<<"$rate")
    q=${quota[$t]}
    h=$(awk -v q="$q" -v r="$rate" 'BEGIN {printf "%.1f", q / (r > 0 ? r : 1) / 3600}')
    hours_all=$(awk -v a="$hours_all" -v h="$h" 'BEGIN {print a + h}')
    quota_table+=$'\n'"| \`fuzz_$t\` | $q | $rate | $h |"
done <<<"$rows"
quota_table+=$'\n'"| in all | 100000000 | | $hours_all |"

# The check: one column per seed.
seeds=()
for f in "$check"/seed*.txt; do
    s=${f##*/seed}
    seeds+=("${s%.txt}")
done
IFS=$'\n' read -r -d '' -a seeds < <(printf '%s\n' "${seeds[@]}" | sort -n && printf '\0')
check_table="| target |"
sep="|---|"
for s in "${seeds[@]}"; do
    check_table+=" seed $s: executions, cov / ft |"
    sep+="---|"
done
check_table+=$'\n'"$sep"
secs=30
for name in $(grep -Eo '^fuzz_[a-z]+-empty' "$check/seed${seeds[0]}.txt" | sed 's/-empty//'); do
    line="| \`$name\` |"
    for s in "${seeds[@]}"; do
        l=$(grep "^$name-empty:" "$check/seed$s.txt" | tail -1)
        if [[ $l =~ ([0-9]+)\ executions\ in\ ([0-9]+)\ s,\ cov:\ ([0-9]+)\ ft:\ ([0-9]+) ]]; then
            secs=${BASH_REMATCH[2]}
            line+=" ${BASH_REMATCH[1]}, ${BASH_REMATCH[3]} / ${BASH_REMATCH[4]}, nothing found |"
        else
            line+=" FOUND: ${l#*: } |"
        fi
    done
    check_table+=$'\n'"$line"
done

mkdir -p "$(dirname "$out")"
# The campaign's commits in order, each once: two calls running side by
# side on one WORK_DIR may both have added it.
awk -v ct="$campaign_table" -v qt="$quota_table" -v kt="$check_table" \
    -v cc="$(awk '!seen[$0]++' "$camp/commit" | paste -sd, | sed 's/,/, then /g')" -v kc="$(cat "$check/commit")" -v m="$machine" \
    -v tot="$total" -v sec="$seconds" -v cs="$secs" '
    { gsub(/@CAMPAIGN_COMMIT@/, cc); gsub(/@CHECK_COMMIT@/, kc); gsub(/@MACHINE@/, m)
      gsub(/@CAMPAIGN_TOTAL@/, tot); gsub(/@CAMPAIGN_SECONDS@/, sec); gsub(/@CHECK_SECONDS@/, cs) }
    /^@CAMPAIGN_TABLE@$/ { print ct; next }
    /^@QUOTA_TABLE@$/ { print qt; next }
    /^@CHECK_TABLE@$/ { print kt; next }
    { print }' "$here/report.md.in" >"$out"
echo "wrote $out"
