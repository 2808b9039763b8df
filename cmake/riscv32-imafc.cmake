# Toolchain file: 32-bit RISC-V rv32imafc, ABI ilp32f: hardware single precision;
# Debian's riscv64-unknown-elf-gcc with picolibc, no OS; the port rv32-virt
# (QEMU's riscv32 virt machine):
#   cmake -S . -B build/rv32imafc -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/riscv32-imafc.cmake
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR riscv32)
set(CMAKE_C_COMPILER riscv64-unknown-elf-gcc)
set(CMAKE_AR riscv64-unknown-elf-ar)
set(CMAKE_RANLIB riscv64-unknown-elf-ranlib)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(CMAKE_C_FLAGS_INIT "-march=rv32imafc -mabi=ilp32f -mcmodel=medany --specs=picolibc.specs")
set(CMAKE_C_FLAGS_MINSIZEREL_INIT "-Os")
set(CMAKE_BUILD_TYPE MinSizeRel CACHE STRING "Build type")
set(PDT_PORT_DEFAULT rv32-virt)
set(PDT_RV32_ARCH rv32imafc)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
