# SPDX-License-Identifier: Apache-2.0
# Copies into OUT the Eigen headers that the Eigen backend includes (the compiler's own list, -MM),
# under their paths below the Eigen root, with Eigen's licence: sources/ then builds without LAPACK
# and without an Eigen installation, and stays small (the headers used, not all of Eigen).
#   cmake -DCXX=... -DEIGEN=<dir with Eigen/> -DSOURCE=linalg_eigen.cpp -DINCLUDES=a;b -DLICENSE=MPL-2.0 -DOUT=dir -P
set(flags "")
foreach(dir IN LISTS INCLUDES)
  list(APPEND flags -I${dir})
endforeach()
execute_process(COMMAND ${CXX} -std=c++17 -MM ${flags} -I${EIGEN} ${SOURCE}
                OUTPUT_VARIABLE deps RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "eigen_headers: ${CXX} -MM ${SOURCE} failed: ${err}")
endif()
string(REPLACE "\\\n" " " deps "${deps}")
separate_arguments(deps UNIX_COMMAND "${deps}")
get_filename_component(root ${EIGEN} REALPATH)
set(count 0)
foreach(dep IN LISTS deps)
  get_filename_component(path ${dep} REALPATH)
  string(FIND "${path}" "${root}/" at)
  if(at EQUAL 0)
    file(RELATIVE_PATH rel ${root} ${path})
    get_filename_component(dir ${OUT}/${rel} DIRECTORY)
    file(MAKE_DIRECTORY ${dir})
    file(COPY_FILE ${path} ${OUT}/${rel} ONLY_IF_DIFFERENT)
    math(EXPR count "${count} + 1")
  endif()
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "eigen_headers: ${SOURCE} includes no header below ${EIGEN}")
endif()
file(COPY_FILE ${LICENSE} ${OUT}/Eigen/COPYING.MPL2 ONLY_IF_DIFFERENT)
