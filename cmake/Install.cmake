# install(EXPORT ...) so another CMake project can find_package(artemis) and link artemis::core.
include(CMakePackageConfigHelpers)
get_property(artemis_modules GLOBAL PROPERTY ARTEMIS_MODULES)
install(TARGETS ${artemis_modules} EXPORT artemisTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS artemis RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The viewer's page and three.js (from viewer/node_modules, installed by scripts/install-deps.sh),
# where the installed program looks for them: <prefix>/share/artemis/viewer.
install(FILES viewer/index.html viewer/app.js viewer/style.css DESTINATION ${CMAKE_INSTALL_DATADIR}/artemis/viewer)
install(DIRECTORY viewer/node_modules/three/build
        DESTINATION ${CMAKE_INSTALL_DATADIR}/artemis/viewer/node_modules/three OPTIONAL)
install(DIRECTORY viewer/node_modules/three/examples/jsm
        DESTINATION ${CMAKE_INSTALL_DATADIR}/artemis/viewer/node_modules/three/examples OPTIONAL)
install(EXPORT artemisTargets NAMESPACE artemis:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/artemis)
configure_package_config_file(cmake/artemisConfig.cmake.in
  ${PROJECT_BINARY_DIR}/artemisConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/artemis)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/artemisConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/artemisConfig.cmake ${PROJECT_BINARY_DIR}/artemisConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/artemis)
