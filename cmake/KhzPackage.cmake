# Package configuration: KilohertzConfig.cmake, KilohertzConfigVersion.cmake and the find
# modules a static build's consumers need for the private dependencies.
include(CMakePackageConfigHelpers)

set(KHZ_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Kilohertz)
if(BUILD_SHARED_LIBS)
  set(KHZ_STATIC_LIBS FALSE)
else()
  set(KHZ_STATIC_LIBS TRUE)
endif()

# Components built only with their option, listed in the config only then.
set(KHZ_OPTIONAL_COMPONENTS "")
if(KHZ_WITH_MPI)
  list(APPEND KHZ_OPTIONAL_COMPONENTS mpi)
endif()

configure_package_config_file(cmake/KilohertzConfig.cmake.in
                              "${PROJECT_BINARY_DIR}/KilohertzConfig.cmake"
                              INSTALL_DESTINATION ${KHZ_INSTALL_CMAKEDIR})
write_basic_package_version_file("${PROJECT_BINARY_DIR}/KilohertzConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/KilohertzConfig.cmake"
              "${PROJECT_BINARY_DIR}/KilohertzConfigVersion.cmake" cmake/FindCHOLMOD.cmake
              cmake/FindARPACK.cmake cmake/FindXXHASH.cmake DESTINATION ${KHZ_INSTALL_CMAKEDIR})
install(FILES LICENSE README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
