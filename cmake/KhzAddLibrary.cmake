# khz_add_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
#
# Creates the library target khz_<name> (alias Kilohertz::<name>, exported as Kilohertz::<name>),
# with public headers in lib<name>/include, a generated export header
# <khz/<name>/export.hpp> (macro KHZ_<NAME>_API) and a generated <khz/<name>/version.hpp>.
include(GenerateExportHeader)

function(khz_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  string(TOUPPER "${name}" upper)
  set(target khz_${name})
  set(generated "${CMAKE_CURRENT_BINARY_DIR}/include")

  add_library(${target} ${ARG_SOURCES})
  add_library(Kilohertz::${name} ALIAS ${target})
  set_target_properties(
    ${target}
    PROPERTIES EXPORT_NAME ${name}
               OUTPUT_NAME khz_${name}
               VERSION ${PROJECT_VERSION}
               SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
               POSITION_INDEPENDENT_CODE ON)
  # Installed, each library finds the Kilohertz libraries it needs beside itself, wherever the
  # prefix is (a run path relative to the library, $ORIGIN): a program that links one component
  # starts without LD_LIBRARY_PATH, since a program's own run path does not serve its libraries'
  # dependencies.
  if(NOT APPLE)
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN")
  endif()
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_include_directories(
    ${target}
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
           $<BUILD_INTERFACE:${generated}>
           $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS}
                                                                    $<BUILD_INTERFACE:khz_warnings>)

  khz_precompile_common_headers(${target})

  generate_export_header(
    ${target} BASE_NAME KHZ_${upper} EXPORT_MACRO_NAME KHZ_${upper}_API
    EXPORT_FILE_NAME "${generated}/khz/${name}/export.hpp")
  if(NOT BUILD_SHARED_LIBS)
    target_compile_definitions(${target} PUBLIC KHZ_${upper}_STATIC_DEFINE)
  endif()
  set(KHZ_LIBRARY_NAME ${name})
  set(KHZ_LIBRARY_UPPER ${upper})
  configure_file("${PROJECT_SOURCE_DIR}/cmake/version.hpp.in" "${generated}/khz/${name}/version.hpp"
                 @ONLY)
  configure_file("${PROJECT_SOURCE_DIR}/cmake/version.cpp.in"
                 "${CMAKE_CURRENT_BINARY_DIR}/src/version.cpp" @ONLY)
  target_sources(${target} PRIVATE "${CMAKE_CURRENT_BINARY_DIR}/src/version.cpp")

  install(
    TARGETS ${target}
    EXPORT Kilohertz_${name}_targets
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  if(EXISTS "${CMAKE_CURRENT_SOURCE_DIR}/include")
    install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
  install(DIRECTORY "${generated}/" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(
    EXPORT Kilohertz_${name}_targets
    NAMESPACE Kilohertz::
    FILE Kilohertz_${name}_targets.cmake
    DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/Kilohertz)
endfunction()
