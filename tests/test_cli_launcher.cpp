// The command under an MPI launcher, as seen from the launcher's environment alone (no MPI
// needed): the processes are read from it, and what cannot run across processes is refused.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "common.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using hemivem::test::CommandRun;
using hemivem::test::scratch;

/// Sets an environment variable for the scope of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    ::setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (had_)
      ::setenv(name_.c_str(), old_.c_str(), 1);
    else
      ::unsetenv(name_.c_str());
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_, old_;
  bool had_ = false;
};

bool under_launcher() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("MV2_COMM_WORLD_SIZE");
}

TEST(Launcher, ProcessesFromTheEnvironment) {
  if (under_launcher()) GTEST_SKIP() << "this test sets the launcher's variables itself";
  EXPECT_EQ(hemivem::cli::launched_processes().size, 1);
  EXPECT_EQ(hemivem::cli::launched_processes().rank, 0);
  {
    ScopedEnv size("OMPI_COMM_WORLD_SIZE", "4"), rank("OMPI_COMM_WORLD_RANK", "3");
    EXPECT_EQ(hemivem::cli::launched_processes().size, 4);
    EXPECT_EQ(hemivem::cli::launched_processes().rank, 3);
    EXPECT_FALSE(hemivem::cli::reporting_process());
  }
  {
    ScopedEnv size("PMI_SIZE", "2"), rank("PMI_RANK", "0");
    EXPECT_EQ(hemivem::cli::launched_processes().size, 2);
    EXPECT_EQ(hemivem::cli::launched_processes().rank, 0);
    EXPECT_TRUE(hemivem::cli::reporting_process());
  }
  {
    ScopedEnv size("MV2_COMM_WORLD_SIZE", "x2");  // not a number: no launcher
    EXPECT_EQ(hemivem::cli::launched_processes().size, 1);
  }
}

TEST(Launcher, SeveralProcessesRefuseOtherEnginesAndCommands) {
  if (under_launcher()) GTEST_SKIP() << "this test sets the launcher's variables itself";
  const fs::path out = scratch("launcher-refused");
  {
    ScopedEnv size("OMPI_COMM_WORLD_SIZE", "2"), rank("OMPI_COMM_WORLD_RANK", "0");
    const CommandRun r = hemivem::test::run_hemivem("solve --n 4 --linear eigen --out " + out.string());
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("use --linear mumps-mpi"), std::string::npos) << r.err;
    const CommandRun c = hemivem::test::run_hemivem("check --n 4");
    EXPECT_EQ(c.code, 2);
    EXPECT_NE(c.err.find("only 'hemivem solve' runs across processes"), std::string::npos) << c.err;
  }
  {
    // rank 1 refuses the same way, silently
    ScopedEnv size("OMPI_COMM_WORLD_SIZE", "2"), rank("OMPI_COMM_WORLD_RANK", "1");
    const CommandRun r = hemivem::test::run_hemivem("solve --n 4 --linear eigen --out " + out.string());
    EXPECT_EQ(r.code, 2);
    EXPECT_TRUE(r.err.empty()) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_FALSE(fs::exists(out));
  {
    ScopedEnv size("OMPI_COMM_WORLD_SIZE", "1"), rank("OMPI_COMM_WORLD_RANK", "0");
    EXPECT_EQ(hemivem::test::run_hemivem("solve --n 4 --linear eigen -q --out " + out.string()).code, 0);
    EXPECT_TRUE(fs::exists(out / "result.json"));
  }
}

}  // namespace
