// main() of the MPI test programs: MPI around GoogleTest. Every rank runs every test (each test
// is collective) and prints its own results; mpiexec fails when any rank fails.

#include <khz/mpi/environment.hpp>

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  const khz::mpi::Environment mpi(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
