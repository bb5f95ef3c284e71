# install(EXPORT ...) so another CMake project can find_package(artemis) and link artemis::core.
include(CMakePackageConfigHelpers)
get_property(artemis_modules GLOBAL PROPERTY ARTEMIS_MODULES)
install(TARGETS ${artemis_modules} EXPORT artemisTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS artemis RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT artemisTargets NAMESPACE artemis:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/artemis)
configure_package_config_file(cmake/artemisConfig.cmake.in
  ${PROJECT_BINARY_DIR}/artemisConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/artemis)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/artemisConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/artemisConfig.cmake ${PROJECT_BINARY_DIR}/artemisConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/artemis)
