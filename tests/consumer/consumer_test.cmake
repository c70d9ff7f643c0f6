# SPDX-License-Identifier: Apache-2.0
# ctest script: install okid into a scratch prefix, then build and run tests/consumer against it
# twice — with find_package(okid) and with pkg-config — as an outside project would.
#   cmake -DBUILD_DIR=<okid build> -DSOURCE_DIR=<tests/consumer> -DWORK_DIR=<scratch> -DCC=<cc> -P consumer_test.cmake
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# 1. CMake package.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/cmake-build -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_C_COMPILER=${CC})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/cmake-build)
run(${WORK_DIR}/cmake-build/okid_consumer)

# 2. pkg-config.
# GNUInstallDirs gives lib or lib/<multiarch> (prefix /usr on Debian): look for the .pc file.
file(GLOB_RECURSE pc_files ${prefix}/*/okid.pc)
if(NOT pc_files)
  message(FATAL_ERROR "no okid.pc installed under ${prefix}")
endif()
list(GET pc_files 0 pc_file)
get_filename_component(pc_dir ${pc_file} DIRECTORY)
set(ENV{PKG_CONFIG_PATH} ${pc_dir})
execute_process(COMMAND pkg-config --cflags --libs okid OUTPUT_VARIABLE flags
                RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not find okid in ${pc_dir}")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${CC} -std=c11 ${SOURCE_DIR}/main.c -o ${WORK_DIR}/pc_consumer ${flags})
run(${WORK_DIR}/pc_consumer)
