# `cmake --install`: the ridge CLI (when built), libridge, its two public headers, a CMake
# package (find_package(ridge) → target ridge::ridge) and a pkg-config file (ridge.pc). Nothing else is installed: the stage
# libraries are linked into libridge, and their headers are internal.
include(CMakePackageConfigHelpers)

set(RIDGE_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/ridge
    CACHE STRING "Where ridgeConfig.cmake is installed, relative to the prefix")

install(TARGETS libridge EXPORT ridgeTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT library
                NAMELINK_COMPONENT development)
install(FILES ${PROJECT_SOURCE_DIR}/include/ridge/ridge.h ${PROJECT_SOURCE_DIR}/include/ridge/error.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/ridge COMPONENT development)
install(EXPORT ridgeTargets NAMESPACE ridge:: DESTINATION ${RIDGE_INSTALL_CMAKEDIR}
        COMPONENT development)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ridgeConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/ridgeConfig.cmake
                              INSTALL_DESTINATION ${RIDGE_INSTALL_CMAKEDIR})
# 0.x: a minor release may change the API, so only the same major.minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ridgeConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ridgeConfig.cmake ${PROJECT_BINARY_DIR}/ridgeConfigVersion.cmake
        DESTINATION ${RIDGE_INSTALL_CMAKEDIR} COMPONENT development)

# pkg-config, for builds that are not CMake: `pkg-config --cflags --libs ridge`. The prefix
# is the one given at install time (cmake --install --prefix), not the configure-time one.
file(READ ${PROJECT_SOURCE_DIR}/cmake/ridge.pc.in ridge_pc_template)
string(CONFIGURE "${ridge_pc_template}" ridge_pc_template @ONLY)
string(REPLACE "prefix=${CMAKE_INSTALL_PREFIX}" "prefix=@RIDGE_PC_PREFIX@" ridge_pc_template
       "${ridge_pc_template}")
file(WRITE ${PROJECT_BINARY_DIR}/ridge.pc.in "${ridge_pc_template}")
install(CODE "set(RIDGE_PC_PREFIX \"\${CMAKE_INSTALL_PREFIX}\")
  set(pc \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig/ridge.pc\")
  message(STATUS \"Installing: \${pc}\")
  configure_file(${PROJECT_BINARY_DIR}/ridge.pc.in \${pc} @ONLY)"
  COMPONENT development)

if(RIDGE_BUILD_CLI)
  install(TARGETS ridge_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
endif()
