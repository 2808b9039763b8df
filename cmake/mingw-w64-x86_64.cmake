# Toolchain file: 64-bit Windows with mingw-w64 (Debian: mingw-w64), for the
# library and the host programs (pdtfit.exe, the demo); the tests that run
# them use Wine (docs/port.md#windows):
#   cmake -S . -B build/mingw -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64-x86_64.cmake
# A cross build makes no host programs by default: pass -DPDT_BUILD_TOOLS=ON.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(PDT_MINGW_PREFIX x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${PDT_MINGW_PREFIX}-gcc)
set(CMAKE_RC_COMPILER ${PDT_MINGW_PREFIX}-windres)
set(CMAKE_AR ${PDT_MINGW_PREFIX}-ar)
set(CMAKE_RANLIB ${PDT_MINGW_PREFIX}-ranlib)
set(CMAKE_FIND_ROOT_PATH /usr/${PDT_MINGW_PREFIX})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
# The programs carry their C runtime's support code, so pdtfit.exe runs
# without the compiler's DLLs beside it.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")
