#!/usr/bin/env bash
# Runs every pdtfit test:
#   1. installs missing dependencies (apt, pip) where it can, else names them;
#   2. the documents' paths and symbols, the layout of the formatted C files
#      (clang-format) and the length of the tools' functions; the numpy
#      reference's own tests and the vectors' reproducibility, the Python
#      package pdtfit (pip install .) against the pdtfit program;
#   3. the CMocka unit tests in the float build, the double build, and the
#      float build under AddressSanitizer + UndefinedBehaviorSanitizer with
#      the library's own expm1/log1p (PDT_MATH_FALLBACK, avr-libc's case)
#      and one vector lane (PDT_VECTOR_LANES 1, a microcontroller's);
#   4. the Cortex-M4F build of lib/ (float and double) under -Werror, a check
#      that it references no allocator, stdio or (float build) double-precision
#      symbol, and its size per module;
#   4a. the proven stack bound of every public function (tools/stack_bound.py),
#      the MISRA C:2012 check of lib/ (tools/misra_check.py) and every fuzz
#      target 5 s on its seeds and 60 s from an empty corpus (tests/fuzz,
#      clang; about 8 minutes);
#   5. pdtfit consumed as a subproject, as a moved install (CMake package,
#      pkg-config) and in Cortex-M0+/M7 firmware builds; the PlatformIO,
#      Arduino, ESP-IDF and Zephyr manifests, and the Arduino example built;
#   6. the target test program on every core with a toolchain file in cmake/
#      (Cortex-M0, M4F, M33, RISC-V rv32imac and rv32imafc; float build)
#      under QEMU, ctest label "target"; before them, the portability steps:
#      clang, the C standards, the Windows build under Wine.
#   6a. lib/ for the ATmega2560 (16-bit int and size_t) at -Werror, its
#      double build refused, and the AVR target test program under simavr,
#      ctest label "target".
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
# ---- portability: Windows (mingw-w64, Wine) and the other cores' toolchains ----
have x86_64-w64-mingw32-gcc || apt_missing+=(mingw-w64)
have wine || apt_missing+=(wine wine64)
have riscv64-unknown-elf-gcc || apt_missing+=(gcc-riscv64-unknown-elf)
[ -d /usr/lib/picolibc/riscv64-unknown-elf ] || apt_missing+=(picolibc-riscv64-unknown-elf)
have qemu-system-riscv32 || apt_missing+=(qemu-system-misc)
# ---- end of portability ----
# --- AVR (step 6a) ---
have avr-gcc || apt_missing+=(gcc-avr)
[ -e /usr/lib/avr/include/avr/io.h ] || apt_missing+=(avr-libc)
have simavr || apt_missing+=(simavr)
# --- end AVR ---
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

step "the identification engine's structure: no figure above its limit"
python3 tools/check_engine_structure.py

step "C layout (.clang-format) and function length in lib/ and tools/"
# Every C file but the generated vectors.
mapfile -t formatted < <(git ls-files '*.c' '*.h' | grep -v '^tests/vectors/')
clang-format --dry-run --Werror "${formatted[@]}"
echo "${#formatted[@]} files formatted as .clang-format says"
# At most 80 lines a function; tools/function_length_allow.txt names the
# library functions still to be split.
python3 tools/check_function_length.py --max 80 --allow tools/function_length_allow.txt lib tools

build_and_test() { # name, extra cmake args...
    local name=$1
    shift
    step "$name build"
    cmake -S "$root" -B "$out/test-$name" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
    cmake --build "$out/test-$name" -j "$jobs"
    ctest --test-dir "$out/test-$name" --output-on-failure -j "$jobs"
}

# -Werror is CI's choice (PDT_WERROR, off by default): every build here sets it.
build_and_test float -DPDT_WERROR=ON -DPDT_PYTHON_TESTS=ON -DPython3_EXECUTABLE="$py"

step "Python package pdtfit against the float build's program"
PDTFIT_BIN="$out/test-float/tools/pdtfit" "$py" -m pytest -q python/tests
build_and_test double -DPDT_WERROR=ON -DPDT_REAL_DOUBLE=ON
# The sanitised build takes a firmware's paths: the library's own expm1
# and log1p, and one vector lane (PDT_VECTOR_LANES 1, a Cortex-M's), so
# that the one-candidate kernel and the per-call bounds of a build without
# lanes are tested on the host too.
build_and_test sanitize -DPDT_WERROR=ON -DPDT_SANITIZE=address,undefined -DCMAKE_BUILD_TYPE=Debug \
    -DPDT_MATH_FALLBACK=ON -DCMAKE_C_FLAGS=-DPDT_VECTOR_LANES=1
# ---- portability: every host compiler (issue: every compiler, Windows) ----
# clang builds everything (library, tools, tests, benchmarks) under its own
# strict warnings as errors, and runs the unit tests (the certainty smoke
# run, label bench, is the gcc builds' alone).
step "clang build"
CC=clang cmake -S "$root" -B "$out/test-clang" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPDT_WERROR=ON >/dev/null
cmake --build "$out/test-clang" -j "$jobs"
ctest --test-dir "$out/test-clang" --output-on-failure -j "$jobs" -L unit
step "lib/ as C99, C11 and C17 with -pedantic-errors, gcc and clang"
bash tools/check_c_standards.sh
# Windows: the library and pdtfit.exe with mingw-w64; the program run under
# Wine against the float build's (tools/check_windows.py). Wine's prefix is
# made once under build/, without a display, its Mono and Gecko prompts off.
step "Windows build (mingw-w64) and pdtfit.exe under Wine against the Linux program"
cmake -S "$root" -B "$out/test-mingw" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/mingw-w64-x86_64.cmake" -DPDT_BUILD_TOOLS=ON \
    -DPDT_WERROR=ON >/dev/null
cmake --build "$out/test-mingw" -j "$jobs"
(
    export WINEPREFIX="$out/wine" WINEARCH=win64 WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
    unset DISPLAY WAYLAND_DISPLAY
    "$py" tools/check_windows.py --linux "$out/test-float/tools/pdtfit" \
        --windows "$out/test-mingw/tools/pdtfit.exe"
)
# ---- end of portability ----

step "Cortex-M4F build of lib/ (float and double), symbols, size per module"
python3 tools/size_report.py --check
tools/check_symbols.sh "$out/size-cm4-float/lib/libpdtfit.a" --float
tools/check_symbols.sh "$out/size-cm4-double/lib/libpdtfit.a"

step "stack bound of every public function on the Cortex-M4F (float and double)"
python3 tools/stack_bound.py --check

step "MISRA C:2012 check of lib/ (cppcheck), against tools/misra_deviations.txt"
python3 tools/misra_check.py

step "fuzz targets (clang, libFuzzer, ASan + UBSan): 5 s on the seeds, 60 s from an empty corpus"
CC=clang cmake -S "$root" -B "$out/test-fuzz" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPDT_WERROR=ON -DPDT_BUILD_FUZZERS=ON -DPDT_BUILD_TESTS=OFF -DPDT_BUILD_TOOLS=OFF -DPDT_INSTALL=OFF >/dev/null
cmake --build "$out/test-fuzz" -j "$jobs"
tests/fuzz/run.sh "$out/test-fuzz" 5 "$out/test-fuzz/fuzz-work" 60

step "consumers (add_subdirectory, moved install, find_package, pkg-config, Cortex-M0+/M7) and package manifests"
bash tools/check_consumers.sh
python3 tools/check_packages.py

# ---- target cores: the target test program of each toolchain file under QEMU ----
# The Cortex-M4F, M33 and rv32imafc run the full program (seconds); the
# soft-float Cortex-M0 and rv32imac the small one (about a minute and a
# half each), docs/port.md#the-cores.
for core in arm-none-eabi-cm4 arm-none-eabi-cm33 arm-none-eabi-cm0 riscv32-imafc riscv32-imac; do
    step "target tests under QEMU: $core"
    cmake -S "$root" -B "$out/test-target-$core" -G Ninja \
        -DCMAKE_TOOLCHAIN_FILE="$root/cmake/$core.cmake" \
        -DPDT_BUILD_TESTS=OFF -DPDT_BUILD_TOOLS=OFF -DPDT_BUILD_TARGET_TESTS=ON -DPDT_WERROR=ON >/dev/null
    cmake --build "$out/test-target-$core" -j "$jobs"
    ctest --test-dir "$out/test-target-$core" -L target --output-on-failure
done
# ---- end of target cores ----

# --- AVR (step 6a; tests/target/avr, cmake/avr-atmega2560.cmake) ---
step "ATmega2560 (16-bit int and size_t): lib/ at -Werror, double refused, target tests under simavr"
if printf '#include "pdt/pdt.h"\n' | avr-gcc -mmcu=atmega2560 -DPDT_REAL_DOUBLE=1 \
    -I lib/include -x c -fsyntax-only - 2>/dev/null; then
    echo "PDT_REAL_DOUBLE=1 compiled for AVR, where double is 32 bits: it must be refused"
    exit 1
fi
echo "PDT_REAL_DOUBLE=1 refused for AVR"
cmake -S "$root" -B "$out/test-avr" -G Ninja \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/avr-atmega2560.cmake" -DPDT_WERROR=ON \
    -DPDT_BUILD_TESTS=OFF -DPDT_BUILD_TOOLS=OFF -DPDT_BUILD_TARGET_TESTS=ON >/dev/null
cmake --build "$out/test-avr" -j "$jobs"
ctest --test-dir "$out/test-avr" -L target --output-on-failure
# --- end AVR ---

step "all tests passed"
