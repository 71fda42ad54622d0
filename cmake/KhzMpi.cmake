# The khz::mpi component (libmpi/): option KHZ_WITH_MPI, on by default when Kilohertz is the
# top-level project and finds MPI with mpiexec and MUMPS (Debian: libopenmpi-dev openmpi-bin
# libmumps-dev). Off, no Kilohertz library links MPI; on, only khz_mpi does.
#
# MPI's C interface, called from C++: FindMPI's CXX component without the C++ bindings MPI 3
# deprecated (MPI_CXX_SKIP_MPICXX; the C component would need the C language enabled).
set(MPI_CXX_SKIP_MPICXX TRUE)
set(khz_mpi_found FALSE)
if(PROJECT_IS_TOP_LEVEL OR KHZ_WITH_MPI)
  find_package(MPI QUIET COMPONENTS CXX)
  # MUMPS, the distributed factorization behind khz::mpi::MumpsFactorization (Debian's
  # libmumps-dev is built against its default MPI).
  find_path(KHZ_MUMPS_INCLUDE_DIR dmumps_c.h)
  find_library(KHZ_DMUMPS_LIBRARY dmumps)
  find_library(KHZ_MUMPS_COMMON_LIBRARY mumps_common)
  if(MPI_CXX_FOUND AND MPIEXEC_EXECUTABLE AND KHZ_MUMPS_INCLUDE_DIR AND KHZ_DMUMPS_LIBRARY
     AND KHZ_MUMPS_COMMON_LIBRARY)
    set(khz_mpi_found TRUE)
  endif()
endif()

option(KHZ_WITH_MPI "Build the khz::mpi component: precomputation shared over MPI ranks"
       ${khz_mpi_found})
if(KHZ_WITH_MPI AND NOT khz_mpi_found)
  message(FATAL_ERROR "KHZ_WITH_MPI is on but no MPI library with mpiexec and MUMPS was found "
                      "(Debian: apt install libopenmpi-dev openmpi-bin libmumps-dev)")
endif()
if(KHZ_WITH_MPI AND NOT TARGET MUMPS::dmumps)
  add_library(MUMPS::dmumps UNKNOWN IMPORTED)
  set_target_properties(
    MUMPS::dmumps PROPERTIES IMPORTED_LOCATION "${KHZ_DMUMPS_LIBRARY}"
                             INTERFACE_INCLUDE_DIRECTORIES "${KHZ_MUMPS_INCLUDE_DIR}"
                             INTERFACE_LINK_LIBRARIES "${KHZ_MUMPS_COMMON_LIBRARY}")
endif()
if(KHZ_WITH_MPI)
  # What the tests and benchmarks pass mpiexec: Open MPI refuses to run as root without
  # --allow-run-as-root, and more ranks than cores without --oversubscribe.
  execute_process(COMMAND "${MPIEXEC_EXECUTABLE}" --version OUTPUT_VARIABLE khz_mpiexec_version
                  ERROR_QUIET)
  set(KHZ_MPIEXEC_FLAGS "")
  if(khz_mpiexec_version MATCHES "OpenRTE|Open MPI|open-mpi")
    set(KHZ_MPIEXEC_FLAGS --oversubscribe --allow-run-as-root)
  endif()
  message(STATUS "Kilohertz MPI component: MPI ${MPI_CXX_VERSION} (${MPIEXEC_EXECUTABLE})")
elseif(PROJECT_IS_TOP_LEVEL)
  message(STATUS "Kilohertz MPI component: off (needs libopenmpi-dev openmpi-bin libmumps-dev)")
endif()
