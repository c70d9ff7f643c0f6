# SPDX-License-Identifier: Apache-2.0
# ctest script: libokid.a must not reference the heap, stdio, process exit or the environment, nor
# (Eigen backend) the C++ runtime: operator new/delete, exceptions and their unwinding, RTTI,
# guarded statics or anything of std:: out of line; and it must hold no writable globals (no state
# shared between identifiers).
#   cmake -DNM=nm -DARCHIVE=libokid.a -P check_archive_symbols.cmake
execute_process(COMMAND ${NM} -u ${ARCHIVE} OUTPUT_VARIABLE undefined RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm -u failed on ${ARCHIVE}")
endif()
set(forbidden malloc calloc realloc free aligned_alloc posix_memalign memalign valloc
    printf fprintf vfprintf puts putchar fputs fwrite perror abort exit _exit getenv
    __printf_chk __fprintf_chk)
foreach(symbol IN LISTS forbidden)
  if(undefined MATCHES "(^|\n)[ \t]*U ${symbol}(\n|$)")
    message(FATAL_ERROR "${ARCHIVE} references ${symbol}")
  endif()
endforeach()

execute_process(COMMAND ${NM} ${ARCHIVE} OUTPUT_VARIABLE all RESULT_VARIABLE rc)
if(all MATCHES "(^|\n)[0-9a-f]+ [BbDdCcGgSs] ([^\n]*)")
  message(FATAL_ERROR "${ARCHIVE} holds writable data: ${CMAKE_MATCH_0}")
endif()
# Itanium C++ ABI names: _Znw/_Zna/_Zdl/_Zda operator new/delete, __cxa_* exceptions and guarded
# statics, __gxx_personality_v0/_Unwind_* unwinding, _ZTI/_ZTS typeinfo, _ZSt/_ZNSt/_ZNKSt std::.
if(undefined MATCHES "(^|\n)[ \t]*U ((_Znw|_Zna|_Zdl|_Zda|__cxa_|__gxx_personality|_Unwind_|_ZTI|_ZTS|_ZSt|_ZNSt|_ZNKSt)[A-Za-z_0-9]*)")
  message(FATAL_ERROR "${ARCHIVE} references the C++ runtime: ${CMAKE_MATCH_2}")
endif()
string(REGEX MATCHALL "U [A-Za-z_0-9]+" refs "${undefined}")
list(LENGTH refs count)
message(STATUS "${ARCHIVE}: ${count} undefined references, none to the heap, stdio, exit or the C++ runtime; no writable data")
