# SPDX-License-Identifier: Apache-2.0
# The include directory of the PyPI package scipy-openblas32 (SciPy's OpenBLAS with LP64 ints and
# every symbol prefixed scipy_), asked from the Python that builds the extension.
if(NOT OKID_SCIPY_OPENBLAS_INCLUDE_DIR)
  find_package(Python 3.9 REQUIRED COMPONENTS Interpreter)
  execute_process(COMMAND ${Python_EXECUTABLE} -c "import scipy_openblas32; print(scipy_openblas32.get_include_dir())"
                  OUTPUT_VARIABLE include_dir OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0 OR NOT EXISTS ${include_dir}/lapacke.h)
    message(FATAL_ERROR "OKID_LAPACK=scipy-openblas32 needs the Python package scipy-openblas32 "
                        "(pip install scipy-openblas32) in ${Python_EXECUTABLE}")
  endif()
  set(OKID_SCIPY_OPENBLAS_INCLUDE_DIR ${include_dir} CACHE PATH "scipy-openblas32's headers")
endif()
