// The main of the test programs: GoogleTest's, run in a temporary directory of the process's
// own. TMPDIR names it for the process and every process it starts (the hemivem command,
// mpiexec, an MPI singleton's daemon). Open MPI keeps its session files in TMPDIR under one
// directory per host and user, and the last process of a job removes that directory when it is
// empty: two test programs starting MPI at the same moment in one TMPDIR race (one creates its
// session directory in the directory the other has just removed, and MPI fails to start).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace {

std::string& own_temporary_directory() {
  static std::string path;
  return path;
}

// Registered before anything that starts MPI, so run after MPI has finished with the directory.
void remove_own_temporary_directory() {
  std::error_code ignored;
  if (!own_temporary_directory().empty()) std::filesystem::remove_all(own_temporary_directory(), ignored);
}

}  // namespace

int main(int argc, char** argv) {
  const char* base = std::getenv("TMPDIR");
  std::string pattern = std::string(base != nullptr && *base != '\0' ? base : "/tmp") + "/hemivem-test.XXXXXX";
  if (mkdtemp(pattern.data()) != nullptr) {
    own_temporary_directory() = pattern;
    setenv("TMPDIR", pattern.c_str(), 1);
    std::atexit(remove_own_temporary_directory);
  }
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
