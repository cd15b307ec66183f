// The entry of the tests that run as several MPI ranks (tests/mpi): MPI starts before the tests
// and ends after them.
#include <gtest/gtest.h>

#include "spall/core/communicator.hpp"

int main(int argc, char** argv) {
  const spall::parallel::Session session;
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
