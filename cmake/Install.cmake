# `cmake --install`: the library, its public headers, the CLI, and the package files that
# let another CMake project `find_package(scanplan)` and link `scanplan::scanplan`.
include(CMakePackageConfigHelpers)

install(TARGETS scanplan EXPORT scanplanTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS scanplan_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/scanplan
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

set(package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/scanplan)
install(EXPORT scanplanTargets NAMESPACE scanplan:: DESTINATION ${package_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/scanplanConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/scanplanConfig.cmake
                              INSTALL_DESTINATION ${package_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/scanplanConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/scanplanConfig.cmake
              ${PROJECT_BINARY_DIR}/scanplanConfigVersion.cmake
        DESTINATION ${package_dir})
