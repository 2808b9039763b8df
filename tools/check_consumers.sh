#!/usr/bin/env bash
# pdtfit as firmware and desk projects consume it (tests/consumer):
#   1. a host project through add_subdirectory: only the library builds, the
#      parent's cache keeps its own build type, the program runs;
#   2. an install (library, headers, CMake package, pkg-config, program)
#      moved to another prefix, then found by find_package and pkg-config;
#   3. Cortex-M0+ and Cortex-M7 firmware through add_subdirectory with
#      arm-none-eabi-gcc: the default target links.
set -euo pipefail
case "${1:-}" in -h | --help) sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
root=$(pwd)
out=$root/build/consumers
rm -rf "$out"
mkdir -p "$out"
c=$root/tests/consumer
q() { "$@" >"$out/last.log" 2>&1 || { cat "$out/last.log"; echo "FAILED: $*"; exit 1; }; }

echo "-- host, add_subdirectory"
q cmake -S "$c" -B "$out/sub" -G Ninja -DPDTFIT_SOURCE_DIR="$root"
q cmake --build "$out/sub"
"$out/sub/consumer"
if grep -q '^CMAKE_BUILD_TYPE:STRING=.\+' "$out/sub/CMakeCache.txt"; then
    echo "FAILED: the subproject set the parent's CMAKE_BUILD_TYPE"; exit 1
fi
for t in pdtfit_port_host pdtfit_port_cm4 pdtfit_cli pdt_demo; do
    if grep -q "build $t\b\|/$t\b" "$out/sub/build.ninja"; then
        echo "FAILED: the subproject builds $t"; exit 1
    fi
done

echo "-- install, moved, find_package and pkg-config"
q cmake -S "$root" -B "$out/lib" -G Ninja -DPDT_BUILD_TESTS=OFF -DCMAKE_INSTALL_PREFIX="$out/stage"
q cmake --build "$out/lib"
q cmake --install "$out/lib"
mv "$out/stage" "$out/moved"
test -x "$out/moved/bin/pdtfit" || { echo "FAILED: pdtfit program not installed"; exit 1; }
if grep -rq "$out/stage\|/usr/lib/x86_64-linux-gnu/libm" "$out/moved/lib/cmake"; then
    echo "FAILED: the installed CMake package names absolute paths"; exit 1
fi
q cmake -S "$c" -B "$out/pkg" -G Ninja -DPDTFIT_USE=package -DCMAKE_PREFIX_PATH="$out/moved"
q cmake --build "$out/pkg"
"$out/pkg/consumer"
pc=$(PKG_CONFIG_PATH="$out/moved/lib/pkgconfig" pkg-config --cflags --libs pdtfit)
echo "pkg-config --cflags --libs pdtfit: $pc"
# shellcheck disable=SC2086
cc -std=c99 -o "$out/pc-consumer" "$c/main.c" $pc
"$out/pc-consumer"
"$out/moved/bin/pdtfit" --help >/dev/null

for cpu in cortex-m0plus cortex-m7; do
    echo "-- $cpu firmware, add_subdirectory"
    q cmake -S "$c" -B "$out/$cpu" -G Ninja -DPDTFIT_SOURCE_DIR="$root" \
        -DCMAKE_TOOLCHAIN_FILE="$c/$cpu.cmake" -DCMAKE_BUILD_TYPE=MinSizeRel
    q cmake --build "$out/$cpu"
    arm-none-eabi-size "$out/$cpu/consumer"
done
echo "consumers: all built"
