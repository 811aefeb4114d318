# `cmake --install`: the cavesim command, the public library, its headers and a CMake package
# (cavesimConfig.cmake, cavesimConfigVersion.cmake, cavesimTargets.cmake with cavesim::cavesim),
# so another project can `find_package(cavesim REQUIRED)` and link `cavesim::cavesim`.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CAVESIM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/cavesim)

install(TARGETS cavesim_lib EXPORT cavesimTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET cavesim)
  install(TARGETS cavesim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(FILES ${PROJECT_SOURCE_DIR}/include/cavesim/cavesim.h ${PROJECT_SOURCE_DIR}/include/cavesim/error.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cavesim)
install(EXPORT cavesimTargets NAMESPACE cavesim:: DESTINATION ${CAVESIM_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/cavesimConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/cavesimConfig.cmake
                              INSTALL_DESTINATION ${CAVESIM_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cavesimConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cavesimConfig.cmake ${PROJECT_BINARY_DIR}/cavesimConfigVersion.cmake
        DESTINATION ${CAVESIM_INSTALL_CMAKEDIR})
