# Toolchain file: ATmega2560 (the Arduino Mega 2560's part) with avr-gcc and
# avr-libc, no OS. 16-bit int and size_t, 32-bit double (the float build
# only: pdt_config.h refuses PDT_REAL_DOUBLE on AVR).
#   cmake -S . -B build-avr -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/avr-atmega2560.cmake
# With -DPDT_BUILD_TARGET_TESTS=ON it builds the target test program of the
# avr-simavr port and registers it with ctest (label target), run by simavr.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR avr)
set(CMAKE_C_COMPILER avr-gcc)
set(CMAKE_AR avr-ar)
set(CMAKE_RANLIB avr-ranlib)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(PDT_AVR_MCU atmega2560 CACHE STRING "avr-gcc -mmcu of the AVR build")
set(PDT_AVR_F_CPU 16000000 CACHE STRING "Clock of the AVR build in Hz (F_CPU)")
# A function and an object per section, so that the link's --gc-sections
# leaves out whatever a program does not call: an Arduino build does the
# same, and the 256 KiB of flash hold the target test program only so.
set(CMAKE_C_FLAGS_INIT
    "-mmcu=${PDT_AVR_MCU} -DF_CPU=${PDT_AVR_F_CPU}UL -ffunction-sections -fdata-sections")
set(CMAKE_C_FLAGS_MINSIZEREL_INIT "-Os")
set(CMAKE_BUILD_TYPE MinSizeRel CACHE STRING "Build type")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
