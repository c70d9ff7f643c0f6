# SPDX-License-Identifier: Apache-2.0
# Cross-compilation for bare-metal RISC-V (rv32imafc, ilp32f: single-precision FPU, compressed
# instructions) with Debian's gcc-riscv64-unknown-elf and picolibc-riscv64-unknown-elf; the GCC
# ships an rv32imafc/ilp32f multilib and picolibc a semihosting variant (crt0-semihost, libsemihost).
# Programs link picolibc's start-up code and linker script (board/riscv-virt sets the memory map).
#
# Debian has no C++ library for riscv64-unknown-elf, and the Eigen backend needs the C++ standard
# headers (templates only: no exceptions, RTTI, heap or C++ runtime; archive_symbols checks the
# library references none). They come from Debian's libstdc++-arm-none-eabi-dev, the same GCC 12
# libstdc++ configured for a bare-metal newlib-family C library, ahead of picolibc's C headers.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR riscv32)

set(CMAKE_C_COMPILER riscv64-unknown-elf-gcc)
set(CMAKE_CXX_COMPILER riscv64-unknown-elf-g++)
set(CMAKE_AR riscv64-unknown-elf-ar)
set(CMAKE_RANLIB riscv64-unknown-elf-ranlib)
set(CMAKE_SIZE riscv64-unknown-elf-size)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(OKID_BOARD riscv-virt CACHE STRING "Board support directory under board/")
set(OKID_TARGET_CPU_FLAGS "-march=rv32imafc -mabi=ilp32f" CACHE STRING
    "Code-generation flags of the target CPU and FPU")
set(picolibc /usr/lib/picolibc/riscv64-unknown-elf)
set(libstdcxx_headers /usr/include/newlib/c++/12.2.1)
# picolibc keeps errno in thread-local storage: local-exec, the only model of a static image.
set(common_flags "${OKID_TARGET_CPU_FLAGS} -ftls-model=local-exec -ffunction-sections -fdata-sections")
set(CMAKE_C_FLAGS_INIT "${common_flags} -isystem ${picolibc}/include")
set(CMAKE_CXX_FLAGS_INIT
    "${common_flags} -isystem ${libstdcxx_headers} -isystem ${libstdcxx_headers}/arm-none-eabi -isystem ${picolibc}/include")
set(CMAKE_EXE_LINKER_FLAGS_INIT "--specs=picolibc.specs --crt0=semihost --oslib=semihost -Wl,--gc-sections")
# Programs link through the C driver even when the library holds C++: there is no libstdc++ to
# link, and a reference to the C++ runtime fails the link.
set(CMAKE_CXX_LINK_EXECUTABLE "<CMAKE_C_COMPILER> <FLAGS> <CMAKE_CXX_LINK_FLAGS> <LINK_FLAGS> <OBJECTS> -o <TARGET> <LINK_LIBRARIES>")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
