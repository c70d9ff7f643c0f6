# SPDX-License-Identifier: Apache-2.0
# 32-bit x86 Linux host build (gcc -m32, Debian gcc-multilib and the i386 libraries that
# scripts/setup.sh installs): size_t is 32 bits as on the firmware targets, and the C tests run
# natively, so the size arithmetic is checked where it can overflow.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR i686)
set(CMAKE_C_COMPILER gcc)
# SSE2 arithmetic, not the x87's 80-bit registers: doubles round as on every other build.
set(CMAKE_C_FLAGS_INIT "-m32 -msse2 -mfpmath=sse")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-m32")
set(CMAKE_LIBRARY_ARCHITECTURE i386-linux-gnu)
# The i386 .pc files (cmocka, lapacke), not the host's.
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/i386-linux-gnu/pkgconfig:/usr/share/pkgconfig")
