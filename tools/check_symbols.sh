#!/usr/bin/env bash
# Fails if a pdtfit archive references an allocator, stdio, rand() or exit:
# lib/ must run where none of them exists. With --float, also fails on any
# double-precision routine (soft-float helpers, double libm): the float
# build must not silently compute in double, which a Cortex-M4F emulates.
# Usage: tools/check_symbols.sh LIB.a [--float]
set -euo pipefail
case "${1:-}" in -h | --help) sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"; exit 0 ;; esac
lib=$1
nm=nm
case "$lib" in *cm4*) nm=arm-none-eabi-nm ;; esac
forbidden='^(malloc|calloc|realloc|free|_malloc_r|_free_r|_calloc_r|_realloc_r|printf|fprintf|sprintf|snprintf|vprintf|vfprintf|puts|fputs|putchar|fputc|fwrite|fopen|fclose|rand|srand|stdout|stderr|_impure_ptr|abort|exit)$'
if [ "${2:-}" = "--float" ]; then
    forbidden="${forbidden%)\$}|__aeabi_d[a-z0-9]*|__aeabi_[fiul]*2d|exp|expm1|log|log1p|pow|sqrt|sin|cos|sinh|cosh|atan|atan2|floor|fabs|hypot)\$"
fi
undefined=$("$nm" -u "$lib" | awk 'NF && $NF !~ /:$/ {print $NF}' | sort -u)
hits=$(echo "$undefined" | grep -E "$forbidden" || true)
if [ -n "$hits" ]; then
    echo "$lib references forbidden symbols:"
    echo "$hits"
    exit 1
fi
echo "$lib: clean${2:+ ($2)}; it needs only: $(echo "$undefined" | grep -v '^pdt_' | tr '\n' ' ')"
