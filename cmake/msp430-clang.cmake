# CMake toolchain file: the C library for the MSP430 (F5xx: MPY32 multiplier)
# with clang (Debian: clang-14 lld-14 llvm-14).
#
#   cmake -S . -B build-msp430 -DCMAKE_TOOLCHAIN_FILE=cmake/msp430-clang.cmake
#   cmake --build build-msp430          # build-msp430/libsigcore.a, MSP430 ELF objects
#
# Only the library: clang ships no start-up code, linker script or runtime
# helpers for the MSP430 (a firmware links its own, e.g. bench/mcu/msp430/;
# examples/firmware/msp430f5510 shows the whole link).
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR msp430)

find_program(SIG_MSP430_CLANG NAMES clang-14 clang REQUIRED)
find_program(SIG_MSP430_AR NAMES llvm-ar-14 llvm-ar REQUIRED)
find_program(SIG_MSP430_RANLIB NAMES llvm-ranlib-14 llvm-ranlib REQUIRED)
set(CMAKE_C_COMPILER ${SIG_MSP430_CLANG})
set(CMAKE_C_COMPILER_TARGET msp430)
set(CMAKE_AR ${SIG_MSP430_AR} CACHE FILEPATH "archiver for MSP430 objects")
set(CMAKE_RANLIB ${SIG_MSP430_RANLIB} CACHE FILEPATH "ranlib for MSP430 objects")
# -mhwmult: every object of a firmware must agree; f5series is the F5510's MPY32.
set(CMAKE_C_FLAGS_INIT "-ffreestanding -mhwmult=f5series -ffunction-sections -fdata-sections")
# No C library to link a test program against: check the compiler with a static library.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
