# SPDX-License-Identifier: Apache-2.0
# The host library's files the identifier FMU compiles in (and ships flat in sources/): the words
# of a refused configuration as the CLI and Python give them (config_explain.c over
# okid_config_check) and the reported modes' rule without heap (mode_windows_rule.c). Included by
# fmu/CMakeLists.txt and by the fuzz build of the same FMU.
set(OKID_FMU_HOST_DIR ${PROJECT_SOURCE_DIR}/host_tools/common)
set(OKID_FMU_HOST_FILES_identifier ${OKID_FMU_HOST_DIR}/config_explain.c ${OKID_FMU_HOST_DIR}/config_explain.h
    ${OKID_FMU_HOST_DIR}/mode_windows_rule.c ${OKID_FMU_HOST_DIR}/mode_windows.h)
