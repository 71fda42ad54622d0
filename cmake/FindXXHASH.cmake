# FindXXHASH: the xxHash library (Debian: libxxhash-dev, which ships no CMake package). Defines
# the imported target XXHASH::XXHASH. XXH3's output is frozen only from xxHash 0.8.0 on, and basis
# files store XXH3 checksums and mesh fingerprints: ask for find_package(XXHASH 0.8).
include(FindPackageHandleStandardArgs)

find_path(XXHASH_INCLUDE_DIR xxhash.h)
find_library(XXHASH_LIBRARY xxhash)

if(XXHASH_INCLUDE_DIR AND EXISTS "${XXHASH_INCLUDE_DIR}/xxhash.h")
  file(STRINGS "${XXHASH_INCLUDE_DIR}/xxhash.h" _xxhash_version_lines
       REGEX "^#define XXH_VERSION_(MAJOR|MINOR|RELEASE) +[0-9]+")
  foreach(_xxhash_part IN ITEMS MAJOR MINOR RELEASE)
    string(REGEX REPLACE ".*#define XXH_VERSION_${_xxhash_part} +([0-9]+).*" "\\1"
                         _xxhash_${_xxhash_part} "${_xxhash_version_lines}")
  endforeach()
  set(XXHASH_VERSION "${_xxhash_MAJOR}.${_xxhash_MINOR}.${_xxhash_RELEASE}")
endif()

find_package_handle_standard_args(
  XXHASH
  REQUIRED_VARS XXHASH_LIBRARY XXHASH_INCLUDE_DIR
  VERSION_VAR XXHASH_VERSION)

if(XXHASH_FOUND AND NOT TARGET XXHASH::XXHASH)
  add_library(XXHASH::XXHASH UNKNOWN IMPORTED)
  set_target_properties(
    XXHASH::XXHASH PROPERTIES IMPORTED_LOCATION "${XXHASH_LIBRARY}"
                              INTERFACE_INCLUDE_DIRECTORIES "${XXHASH_INCLUDE_DIR}")
endif()
mark_as_advanced(XXHASH_INCLUDE_DIR XXHASH_LIBRARY)
