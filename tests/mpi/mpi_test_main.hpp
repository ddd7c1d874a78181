// The main() of the GoogleTest programs run under mpiexec: every rank runs every test; rank 0
// prints GoogleTest's usual report, the other ranks print only their failures (each line
// prefixed with the rank); the program fails on every rank when a test failed on any.
#pragma once

#include <hemivem/mumps_mpi_factorization.hpp>

#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>

namespace hemivem::test {

class RankFailurePrinter : public ::testing::EmptyTestEventListener {
 public:
  explicit RankFailurePrinter(int rank) : rank_(rank) {}
  void OnTestPartResult(const ::testing::TestPartResult& result) override {
    if (result.failed())
      std::fprintf(stderr, "[rank %d] %s:%d: failure\n%s\n", rank_,
                   result.file_name() ? result.file_name() : "?", result.line_number(), result.summary());
  }

 private:
  int rank_;
};

/// Runs every test on every rank; `title` is printed by rank 0 with the number of processes.
/// The engine initializes MPI (and finalizes it at exit) when the program has not.
inline int run_tests_on_every_rank(int argc, char** argv, const char* title) {
  const int my_rank = MumpsMpiFactorization::mpi_rank();
  const int size = MumpsMpiFactorization::mpi_size();
  ::testing::InitGoogleTest(&argc, argv);
  if (my_rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new RankFailurePrinter(my_rank));
  } else {
    std::printf("%s on %d MPI process%s\n", title, size, size > 1 ? "es" : "");
  }
  const int failed_here = RUN_ALL_TESTS() != 0 ? 1 : 0;
  int failed_anywhere = 0;
  MPI_Allreduce(&failed_here, &failed_anywhere, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (my_rank == 0 && failed_anywhere && !failed_here)
    std::printf("FAILED on a process other than rank 0 (see its output above)\n");
  return failed_anywhere;
}

}  // namespace hemivem::test
