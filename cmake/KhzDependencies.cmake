# Third-party dependencies, all from Debian packages (scripts/setup-debian installs them).
#
# Eigen is part of the public interface. SuiteSparse (CHOLMOD), ARPACK, LAPACK, CGAL, xxHash and
# nlohmann/json are private implementation details: they never appear in an installed header.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Threads REQUIRED)
find_package(OpenMP REQUIRED COMPONENTS CXX)  # element loops (GCC's libgomp)
find_package(CHOLMOD REQUIRED)
find_package(ARPACK REQUIRED)
find_package(LAPACK REQUIRED)  # dense QR of tall sample matrices (OpenBLAS on Debian)
find_package(XXHASH 0.8 REQUIRED)  # XXH3 checksums and mesh fingerprints (frozen from 0.8.0)
find_package(nlohmann_json 3 REQUIRED)  # scene files (libscene, header-only)
# CGAL warns when it is not the one choosing the build type; we choose it above.
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL 5.5 REQUIRED)
