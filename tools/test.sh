#!/usr/bin/env bash
# Runs every pdtfit test:
#   1. installs missing dependencies (apt, pip) where it can, else names them;
#   2. the documents' paths and symbols, the layout of the formatted C files
#      (clang-format) and the length of the tools' functions; the numpy
#      reference's own tests and the vectors' reproducibility, the Python
#      package pdtfit (pip install .) against the pdtfit program;
#   3. the CMocka unit tests in the float build, the double build, and the
#      float build under AddressSanitizer + UndefinedBehaviorSanitizer;
#   4. the Cortex-M4F build of lib/ (float and double) under -Werror, a check
#      that it references no allocator, stdio or (float build) double-precision
#      symbol, and its size per module;
#   4a. the proven stack bound of every public function (tools/stack_bound.py),
#      the MISRA C:2012 check of lib/ (tools/misra_check.py) and every fuzz
#      target for a few seconds (tests/fuzz, clang);
#   5. pdtfit consumed as a subproject, as a moved install (CMake package,
#      pkg-config) and in Cortex-M0+/M7 firmware builds; the PlatformIO,
#      Arduino, ESP-IDF and Zephyr manifests, and the Arduino example built;
#   6. the target test program on the Cortex-M4F (float build) under QEMU
#      (mps2-an386), ctest label "target".
# Build trees go to build/test-*; nothing outside the checkout is written
# except by the package installers.
set -euo pipefail
case "${1:-}" in -h | --help) sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0"; exit 0 ;; esac
cd "$(dirname "$0")/.."
# Tests that need the pdtfit program fail here instead of skipping.
export PDTFIT_REQUIRE_BIN=1
root=$(pwd)
out=$root/build
jobs=$(nproc 2>/dev/null || echo 2)

step() { printf '\n==== %s\n' "$*"; }
have() { command -v "$1" >/dev/null 2>&1; }

step "dependencies"
apt_missing=()
have cmake || apt_missing+=(cmake)
have ninja || apt_missing+=(ninja-build)
have gcc || apt_missing+=(gcc)
have python3 || apt_missing+=(python3 python3-pip)
[ -e /usr/include/cmocka.h ] || apt_missing+=(libcmocka-dev)
have arm-none-eabi-gcc || apt_missing+=(gcc-arm-none-eabi)
[ -e /usr/include/newlib/math.h ] || apt_missing+=(libnewlib-arm-none-eabi)
have qemu-system-arm || apt_missing+=(qemu-system-arm)
have pkg-config || apt_missing+=(pkg-config)
have clang-format || apt_missing+=(clang-format)
have clang || apt_missing+=(clang)
# libFuzzer's runtime (tests/fuzz) is packaged apart from clang on Debian.
ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1 ||
    apt_missing+=(libclang-rt-14-dev)
have cppcheck || apt_missing+=(cppcheck)
if ((${#apt_missing[@]})); then
    if [ "$(id -u)" = 0 ] && have apt-get; then
        apt-get update -q
        DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${apt_missing[@]}"
    elif have sudo && sudo -n true 2>/dev/null; then
        sudo apt-get update -q
        sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${apt_missing[@]}"
    else
        echo "missing Debian packages: ${apt_missing[*]}"
        echo "install them with: sudo apt-get install ${apt_missing[*]}"
        exit 1
    fi
fi
if ! python3 tools/check_requirements.py tools/requirements.txt; then
    python3 -m pip install -q -r tools/requirements.txt ||
        python3 -m pip install -q --break-system-packages -r tools/requirements.txt || {
        echo "could not install the Python packages in tools/requirements.txt with pip"
        exit 1
    }
    python3 tools/check_requirements.py tools/requirements.txt
fi
echo "all dependencies present"

# The Python packages go into a virtual environment that sees the pinned
# packages above: pdtfit (pip install . builds the library as a shared
# object) and the tools' packages, editable (pdtref, vectorgen, pdtsupport,
# pdtrepro, pdtbench), so that no script edits sys.path.
step "Python packages: pdtfit and the tools"
venv=$out/venv
[ -x "$venv/bin/python" ] || python3 -m venv --system-site-packages --without-pip "$venv"
py=$venv/bin/python
"$py" -m pip install -q -e tools .

step "documents: every path and symbol they name exists"
"$py" tools/check_docs.py

step "C layout (.clang-format) and function length in tools/"
# Every C file but the generated vectors.
mapfile -t formatted < <(git ls-files '*.c' '*.h' | grep -v '^tests/vectors/')
clang-format --dry-run --Werror "${formatted[@]}"
echo "${#formatted[@]} files formatted as .clang-format says"
python3 tools/check_function_length.py --max 80 tools

build_and_test() { # name, extra cmake args...
    local name=$1
    shift
    step "$name build"
    cmake -S "$root" -B "$out/test-$name" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
    cmake --build "$out/test-$name" -j "$jobs"
    ctest --test-dir "$out/test-$name" --output-on-failure -j "$jobs"
}

build_and_test float -DPDT_PYTHON_TESTS=ON -DPython3_EXECUTABLE="$py"

step "Python package pdtfit against the float build's program"
PDTFIT_BIN="$out/test-float/tools/pdtfit" "$py" -m pytest -q python/tests
build_and_test double -DPDT_REAL_DOUBLE=ON
build_and_test sanitize -DPDT_SANITIZE=address,undefined -DCMAKE_BUILD_TYPE=Debug

step "Cortex-M4F build of lib/ (float and double), symbols, size per module"
python3 tools/size_report.py --check
tools/check_symbols.sh "$out/size-cm4-float/lib/libpdtfit.a" --float
tools/check_symbols.sh "$out/size-cm4-double/lib/libpdtfit.a"

step "stack bound of every public function on the Cortex-M4F (float and double)"
python3 tools/stack_bound.py --check

step "MISRA C:2012 check of lib/ (cppcheck), against tools/misra_deviations.txt"
python3 tools/misra_check.py

step "fuzz targets (clang, libFuzzer, ASan + UBSan), a few seconds each"
CC=clang cmake -S "$root" -B "$out/test-fuzz" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPDT_BUILD_FUZZERS=ON -DPDT_BUILD_TESTS=OFF -DPDT_BUILD_TOOLS=OFF -DPDT_INSTALL=OFF >/dev/null
cmake --build "$out/test-fuzz" -j "$jobs"
tests/fuzz/run.sh "$out/test-fuzz" 5

step "consumers (add_subdirectory, moved install, find_package, pkg-config, Cortex-M0+/M7) and package manifests"
bash tools/check_consumers.sh
python3 tools/check_packages.py

step "Cortex-M4F target tests under QEMU"
cmake -S "$root" -B "$out/test-target" -G Ninja \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/arm-none-eabi-cm4.cmake" \
    -DPDT_BUILD_TESTS=OFF -DPDT_BUILD_TOOLS=OFF -DPDT_BUILD_TARGET_TESTS=ON >/dev/null
cmake --build "$out/test-target" -j "$jobs"
ctest --test-dir "$out/test-target" -L target --output-on-failure

step "all tests passed"
