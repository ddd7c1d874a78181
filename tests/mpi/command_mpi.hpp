// What the tests of the hemivem command under mpiexec share (test_cli_mpi.cpp,
// test_cli_full_space_mpi.cpp): the command lines of mpiexec and the command, compiled in by
// hemivem_add_command_mpi_test (CMakeLists.txt), scratch folders and a count of messages.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace hemivem::test::mpi {

using hemivem::test::CommandRun;
using hemivem::test::slurp;

inline CommandRun run(const std::string& command) { return run_command(command); }

inline std::string mpiexec() { return std::string(HEMIVEM_MPIEXEC) + " " + HEMIVEM_MPIEXEC_FLAGS; }
inline std::string np(int n) { return std::string(HEMIVEM_MPIEXEC_NUMPROC_FLAG) + " " + std::to_string(n); }
inline std::string binary() { return HEMIVEM_BINARY; }

/// An empty scratch path `name` of the tests `suite` of this process (removed if it exists).
inline std::filesystem::path scratch(const std::string& suite, const std::string& name) {
  const std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("hemivem-mpi-" + suite + "-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(p);
  return p;
}

/// How many times `what` occurs in `text`.
inline std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

}  // namespace hemivem::test::mpi
