#!/usr/bin/env bash
# Compiles every source of lib/ as C99, C11 and C17, strictly (-pedantic-errors
# and the library's warning set as errors), with gcc and clang, in the float
# and the double build. The library is C99; this proves it is also valid in
# the later standards a firmware project may compile it under.
#   tools/check_c_standards.sh [compiler...]   (default: gcc clang)
# Front end only (-fsyntax-only): the optimised builds of tools/test.sh see
# the warnings that need the optimiser.
case "${1:-}" in -h | --help) sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
compilers=("$@")
((${#compilers[@]})) || compilers=(gcc clang)
# The set of the top-level CMakeLists.txt (PDT_STRICT_WARNINGS).
strict=$(sed -n '/^set(PDT_STRICT_WARNINGS/,/)/p' CMakeLists.txt |
    sed 's/^set(PDT_STRICT_WARNINGS//; s/)//' | tr '\n' ' ')
[[ $strict == *-Wall* ]] || {
    echo "no PDT_STRICT_WARNINGS in CMakeLists.txt"
    exit 1
}
jobs=$(nproc 2>/dev/null || echo 2)
failed=0
for cc in "${compilers[@]}"; do
    for std in c99 c11 c17; do
        for real in 0 1; do
            # shellcheck disable=SC2086 # the warning set is a word list
            if ! printf '%s\0' lib/src/*.c |
                xargs -0 -n 8 -P "$jobs" "$cc" -std="$std" -pedantic-errors $strict -Werror \
                    -DPDT_REAL_DOUBLE="$real" -Ilib/include -Ilib/src -fsyntax-only; then
                echo "FAIL $cc -std=$std PDT_REAL_DOUBLE=$real"
                failed=1
            else
                echo "ok   $cc -std=$std PDT_REAL_DOUBLE=$real"
            fi
        done
    done
done
exit "$failed"
