// The main() of the GoogleTest programs of the full-space route run under mpiexec, through
// hemivem::krylov (krylov_world, process_rows) rather than MPI itself: every process runs every
// test, the first prints GoogleTest's report, and the program fails on every process when a test
// failed on any (a process's own failures named on stderr).
#pragma once

#include <hemivem/krylov_solver.hpp>

#include <gtest/gtest.h>

#include <cstdio>

namespace hemivem::test {

/// Runs every test on every process; `title` is printed by the first with the number of processes.
inline int run_tests_on_every_process(int argc, char** argv, const char* title) {
  const ProcessWorld world = krylov_world();
  ::testing::InitGoogleTest(&argc, argv);
  if (world.rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  } else {
    std::printf("%s on %d process%s\n", title, world.size, world.size > 1 ? "es" : "");
  }
  const int failed_here = RUN_ALL_TESTS() != 0 ? 1 : 0;
  const double failed = process_rows()->max(failed_here);
  if (failed_here) std::fprintf(stderr, "tests failed on rank %d\n", world.rank);
  return failed > 0.0 ? 1 : 0;
}

}  // namespace hemivem::test
