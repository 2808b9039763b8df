#!/usr/bin/env bash
# The fuzzing's done-when check (docs/fuzzing.md): every target of a
# PDT_BUILD_FUZZERS build run SECONDS from an empty corpus with its
# dictionary, once per fuzzer seed given (tests/fuzz/run.sh with -seed=),
# one target at a time, at nice 10. The output of each round goes to
# WORK_DIR/seed<N>.txt; tests/fuzz/report.sh turns them into a table.
#
# Usage: tests/fuzz/check.sh BUILD_DIR WORK_DIR SECONDS SEED...
# Exits non-zero if any run found something.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
work=$2
secs=$3
shift 3
mkdir -p "$work"
git -C "$here" rev-parse --short HEAD >"$work/commit"
status=0
for seed in "$@"; do
    nice -n 10 "$here/run.sh" "$build" 0 "$work/seed$seed" "$secs" -seed="$seed" \
        >"$work/seed$seed.txt" 2>&1 || status=1
    cat "$work/seed$seed.txt"
done
exit $status
