# SPDX-License-Identifier: Apache-2.0
# Install rules: libokid.a, the public headers, a CMake package (find_package(okid) -> okid::okid)
# and a pkg-config file. The CLI installs itself from host_tools/cli.
include(CMakePackageConfigHelpers)

install(TARGETS okid EXPORT okidTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/include/okid DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/lib/include/okid/okid_build_config.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/okid)

set(OKID_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/okid)
install(EXPORT okidTargets NAMESPACE okid:: DESTINATION ${OKID_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/okidConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/okidConfig.cmake INSTALL_DESTINATION ${OKID_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/okidConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/okidConfig.cmake ${PROJECT_BINARY_DIR}/okidConfigVersion.cmake
        DESTINATION ${OKID_CMAKE_DIR})

# Relocatable: the prefix is found from the .pc file's own place, so `cmake --install --prefix` works.
file(RELATIVE_PATH OKID_PC_TO_PREFIX "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
configure_file(${PROJECT_SOURCE_DIR}/cmake/okid.pc.in ${PROJECT_BINARY_DIR}/okid.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/okid.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
