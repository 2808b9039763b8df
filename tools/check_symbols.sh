#!/usr/bin/env bash
# Fails if the library archive references an allocator, stdio or rand():
# lib/ must run where none of them exists.
set -euo pipefail
lib=$1
nm=nm
case "$(basename "$(dirname "$(dirname "$lib")")")" in *cm4*) nm=arm-none-eabi-nm ;; esac
forbidden='^(malloc|calloc|realloc|free|_malloc_r|_free_r|_calloc_r|_realloc_r|printf|fprintf|sprintf|snprintf|vprintf|vfprintf|puts|fputs|putchar|fputc|fwrite|fopen|fclose|rand|srand|stdout|stderr|_impure_ptr|abort|exit)$'
hits=$("$nm" -u "$lib" | awk '{print $NF}' | grep -E "$forbidden" | sort -u || true)
if [ -n "$hits" ]; then
    echo "$lib references forbidden symbols:"
    echo "$hits"
    exit 1
fi
echo "$lib: no allocator, stdio, rand or exit symbols; undefined symbols are:"
"$nm" -u "$lib" | awk '{print $NF}' | sort -u | tr '\n' ' '
echo
