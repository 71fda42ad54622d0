# CGAL's demo meshes (Debian package libcgal-demo) are the project's real test meshes. They are
# extracted from the package's archive into the build tree at configure time; the path reaches
# C++ through generated headers. A missing package is a configure error, never a skipped test.

set(KHZ_CGAL_DATA_ARCHIVE "/usr/share/doc/libcgal-dev/data.tar.gz"
    CACHE FILEPATH "CGAL's data archive (Debian package libcgal-demo)")

if(NOT EXISTS "${KHZ_CGAL_DATA_ARCHIVE}")
  message(FATAL_ERROR "CGAL's demo data '${KHZ_CGAL_DATA_ARCHIVE}' is missing. "
                      "Run scripts/setup-debian (installs libcgal-demo) or set "
                      "KHZ_CGAL_DATA_ARCHIVE.")
endif()

set(KHZ_CGAL_MESH_DIR "${PROJECT_BINARY_DIR}/cgal-data/data/meshes")
if(NOT EXISTS "${KHZ_CGAL_MESH_DIR}/dino.off")
  message(STATUS "Extracting CGAL demo meshes to ${KHZ_CGAL_MESH_DIR}")
  file(ARCHIVE_EXTRACT INPUT "${KHZ_CGAL_DATA_ARCHIVE}" DESTINATION "${PROJECT_BINARY_DIR}/cgal-data"
       PATTERNS "data/meshes/*")
endif()
