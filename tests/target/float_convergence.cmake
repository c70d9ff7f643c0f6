# SPDX-License-Identifier: Apache-2.0
# The float convergence test (docs/accuracy.md), for the host float build (tests/CMakeLists.txt)
# and a float target (tests/target/CMakeLists.txt): test_float_convergence built here with this
# build's okid_real = float, the same program built for the host in double (the host twin project,
# same backend), and a test that holds the two runs' errors side by side on the same record.
#   okid_add_float_convergence_test(<runner words...>): runner words before the program (QEMU on a
#   target, nothing on the host); OKID_CONVERGENCE_CHECKPOINTS: the record lengths.
include(ExternalProject)
set(OKID_CONVERGENCE_SOURCE_DIR ${CMAKE_CURRENT_LIST_DIR})

function(okid_add_float_convergence_test)
  set(checkpoints ${OKID_CONVERGENCE_CHECKPOINTS})
  add_executable(test_float_convergence ${OKID_CONVERGENCE_SOURCE_DIR}/test_float_convergence.c)
  target_link_libraries(test_float_convergence PRIVATE okid::okid ${OKID_CONVERGENCE_EXTRA_LIBRARIES})
  target_compile_definitions(test_float_convergence PRIVATE "CONVERGENCE_CHECKPOINTS=${checkpoints}")

  set(twin_dir ${CMAKE_CURRENT_BINARY_DIR}/double_twin)
  ExternalProject_Add(okid_double_twin
    SOURCE_DIR ${OKID_CONVERGENCE_SOURCE_DIR}/host_twin
    BINARY_DIR ${twin_dir}
    CMAKE_GENERATOR ${CMAKE_GENERATOR}
    CMAKE_ARGS -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=cc -DCMAKE_CXX_COMPILER=c++
               -DOKID_REAL=double -DOKID_BACKEND=${OKID_BACKEND} -DOKID_EIGEN_MAX_ORDER=${OKID_EIGEN_MAX_ORDER}
               "-DCONVERGENCE_CHECKPOINTS=${checkpoints}"
    BUILD_COMMAND ${CMAKE_COMMAND} --build ${twin_dir} --target test_float_convergence_host
    INSTALL_COMMAND ""
    BUILD_ALWAYS ON
    BUILD_BYPRODUCTS ${twin_dir}/test_float_convergence_host)

  string(JOIN "|" float_cmd ${ARGN} $<TARGET_FILE:test_float_convergence>)
  add_test(NAME float_convergence
           COMMAND ${CMAKE_COMMAND} "-DFLOAT_CMD=${float_cmd}" -DDOUBLE_CMD=${twin_dir}/test_float_convergence_host
                   -P ${OKID_CONVERGENCE_SOURCE_DIR}/compare_convergence.cmake)
endfunction()
