#!/usr/bin/env bash
# Builds pdtfit (float) and runs the demo. Needs gcc, cmake and ninja; installs
# them with apt when run as root on Debian and they are missing.
set -euo pipefail
case "${1:-}" in -h | --help) sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
missing=()
for tool in gcc cmake ninja; do
    command -v $tool >/dev/null 2>&1 || missing+=("$([ $tool = ninja ] && echo ninja-build || echo $tool)")
done
if ((${#missing[@]})); then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}"
    else
        echo "missing: ${missing[*]} (apt-get install ${missing[*]})"
        exit 1
    fi
fi
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DPDT_BUILD_TESTS=OFF >/dev/null
cmake --build build/release --target pdt_demo pdtfit_cli >/dev/null
exec build/release/tools/pdt_demo "$@"
