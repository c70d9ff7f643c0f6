# SPDX-License-Identifier: Apache-2.0
# Cross-compilation for bare-metal Cortex-M with Debian's gcc-arm-none-eabi and newlib.
# The CPU flags come from the preset (OKID_TARGET_CPU_FLAGS), e.g.
#   -mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard
# Programs link newlib's semihosting (rdimon) and the board's own start-up code (board/mps2).
set(OKID_BOARD mps2 CACHE STRING "Board support directory under board/")
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_AR arm-none-eabi-ar)
set(CMAKE_RANLIB arm-none-eabi-ranlib)
set(CMAKE_SIZE arm-none-eabi-size)
# No operating system to link a test program against while CMake probes the compiler.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(OKID_TARGET_CPU_FLAGS "-mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard" CACHE STRING
    "Code-generation flags of the target CPU and FPU")
# Sections per function and per object, so --gc-sections keeps only what a program calls.
set(CMAKE_C_FLAGS_INIT "${OKID_TARGET_CPU_FLAGS} -mthumb -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_C_FLAGS_INIT}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "--specs=rdimon.specs -nostartfiles -Wl,--gc-sections")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
