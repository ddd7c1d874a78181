// Outputs as one transaction (hemivem/support/output_folder.hpp): a failed write, a signal
// during the writing or a second writer never leave a folder mixing two runs or a truncated
// file, and what killed runs left beside the folder goes. The command-line cases run the
// built binary with the test hooks HEMIVEM_TEST_FAIL_WRITE and HEMIVEM_TEST_WRITE_DELAY.
#include <hemivem/support/atomic_file.hpp>
#include <hemivem/support/output_folder.hpp>
#include <hemivem/error.hpp>
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace hemivem;
namespace fs = std::filesystem;
using hemivem::test::run_command;
using hemivem::test::slurp;

namespace {

/// A fresh folder holding the output folder `out` of the tests, removed at the end.
struct Scratch {
  fs::path root = hemivem::test::scratch("transaction");
  fs::path out = root / "out";
  Scratch() { fs::create_directories(root); }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
};

/// Every file under `dir` (names relative to it) with its contents.
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) files[e.path().filename().string()] = slurp(e.path());
  return files;
}

/// The names in `root` other than `out` (what a run left beside the output folder).
std::vector<std::string> beside(const fs::path& root) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(root))
    if (e.path().filename() != "out" && e.path().filename() != "stderr.txt") names.push_back(e.path().filename().string());
  return names;
}

const std::string kSolve = " solve -q --set mesh.n=8 --out ";

/// A solve into `out` with the given environment; returns its exit code and standard error.
hemivem::test::CommandRun solve(const fs::path& out, const std::string& env = "", const std::string& set = "") {
  return run_command(env + " " + HEMIVEM_BINARY + kSolve + out.string() + " " + set);
}

/// Starts `hemivem solve` into `out`, each written file delayed by `delay` seconds, its standard
/// error into `err` (discarded when empty); returns its id.
pid_t start_slow_solve(const fs::path& out, const std::string& delay, const std::string& set = "",
                       const fs::path& err = {}) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setenv("HEMIVEM_TEST_WRITE_DELAY", delay.c_str(), 1);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(err.empty() ? null : ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644), 2);
    const std::string cmd = std::string("exec ") + HEMIVEM_BINARY + kSolve + out.string() + " " + set;
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

/// Waits (at most 60 s) until a run writes its set beside `out` (.out.hemivem-new.PID holds a file).
bool writing_started(const fs::path& out, pid_t pid) {
  const fs::path staging = out.parent_path() / (".out.hemivem-new." + std::to_string(pid));
  for (int i = 0; i < 600; ++i) {
    std::error_code ec;
    if (fs::exists(staging / "result.json", ec)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

int wait_for(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

/// A process id that no longer runs.
pid_t gone_pid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  wait_for(pid);
  return pid;
}

void expect_previous_set_after_signal(int signal) {
  Scratch s;
  ASSERT_EQ(solve(s.out).code, 0);
  const auto before = contents(s.out);
  const pid_t pid = start_slow_solve(s.out, "0.5", "--set contact.gap=0.0123", s.root / "stderr.txt");
  ASSERT_TRUE(writing_started(s.out, pid)) << "the run never started writing beside the folder";
  ::kill(pid, signal);
  const int status = wait_for(pid);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), signal) << "the signal is the run's exit status";
  EXPECT_EQ(contents(s.out), before) << "the folder must hold the complete previous set";
  // it says so, naming the signal
  const std::string said = slurp(s.root / "stderr.txt");
  EXPECT_NE(said.find(std::string("hemivem: interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") + ": " +
                      s.out.string() + " keeps its previous outputs\n"),
            std::string::npos)
      << said;
  // the next run removes what the killed one left and writes its complete set
  ASSERT_EQ(solve(s.out, "", "--set contact.gap=0.0123").code, 0);
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
  EXPECT_NE(contents(s.out).at("result.json"), before.at("result.json"));
}

}  // namespace

TEST(OutputTransaction, InjectedWriteFailureKeepsThePreviousSet) {
  Scratch s;
  ASSERT_EQ(solve(s.out).code, 0);
  const auto before = contents(s.out);
  ASSERT_EQ(before.size(), 10u);
  for (const char* n : {"1", "3", "9"}) {  // the first file, one in the middle, a figure or the last
    const auto run = solve(s.out, std::string("HEMIVEM_TEST_FAIL_WRITE=") + n, "--set contact.gap=0.0123");
    EXPECT_EQ(run.code, 2) << n;
    EXPECT_NE(run.err.find("No space left on device"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("keeps its previous outputs"), std::string::npos) << run.err;
    EXPECT_EQ(contents(s.out), before) << "write " << n;
    EXPECT_EQ(beside(s.root), std::vector<std::string>{}) << "write " << n;
  }
}

// A loading path writes its steps into the transaction while it solves them: a write that fails
// then (path.json, opened before the first step; a frame) or after leaves the previous set whole.
TEST(OutputTransaction, APathWritingAsItRunsKeepsThePreviousSetWhenAWriteFails) {
  Scratch s;
  const std::string path = "--set path.steps=4 --set 'output.write=[\"result-json\",\"vtu\"]'";
  ASSERT_EQ(solve(s.out, "", path).code, 0);
  const auto before = contents(s.out);
  ASSERT_EQ(before.count("solution-0004.vtu"), 1u);
  ASSERT_EQ(before.count("path-contact.csv"), 1u);
  for (const char* n : {"1", "4", "8"}) {  // path.json, a frame while the path runs, a file after it
    const auto run = solve(s.out, std::string("HEMIVEM_TEST_FAIL_WRITE=") + n, path + " --set contact.gap=0.0123");
    EXPECT_EQ(run.code, 2) << n;
    EXPECT_NE(run.err.find("No space left on device"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("keeps its previous outputs"), std::string::npos) << run.err;
    EXPECT_EQ(contents(s.out), before) << "write " << n;
    EXPECT_EQ(beside(s.root), std::vector<std::string>{}) << "write " << n;
  }
  ASSERT_EQ(solve(s.out, "", path + " --set contact.gap=0.0123").code, 0);
  EXPECT_NE(contents(s.out).at("path.json"), before.at("path.json"));
}

TEST(OutputTransaction, InjectedWriteFailureOnAFirstRunLeavesNoFolder) {
  Scratch s;
  const auto run = solve(s.out, "HEMIVEM_TEST_FAIL_WRITE=2");
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.err.find("no outputs were written to"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(s.out));
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
}

TEST(OutputTransaction, SigtermDuringWritingLeavesThePreviousSet) { expect_previous_set_after_signal(SIGTERM); }

TEST(OutputTransaction, AnInterruptedFirstRunSaysItWroteNothing) {
  Scratch s;
  const pid_t pid = start_slow_solve(s.out, "0.5", "", s.root / "stderr.txt");
  ASSERT_TRUE(writing_started(s.out, pid)) << "the run never started writing beside the folder";
  ::kill(pid, SIGINT);
  const int status = wait_for(pid);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  EXPECT_FALSE(fs::exists(s.out));
  const std::string said = slurp(s.root / "stderr.txt");
  EXPECT_NE(said.find("hemivem: interrupted by SIGINT: no outputs were written to " + s.out.string()), std::string::npos)
      << said;
}

TEST(OutputTransaction, SigintDuringWritingLeavesThePreviousSet) { expect_previous_set_after_signal(SIGINT); }

TEST(OutputTransaction, ASecondWriterIsRefused) {
  Scratch s;
  const pid_t first = start_slow_solve(s.out, "0.3");
  ASSERT_TRUE(writing_started(s.out, first));
  const auto second = solve(s.out, "", "--set contact.gap=0.0123");
  EXPECT_EQ(second.code, 2);
  EXPECT_NE(second.err.find("another hemivem run is writing " + s.out.string()), std::string::npos) << second.err;
  const int status = wait_for(first);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(contents(s.out).size(), 10u);
  EXPECT_EQ(contents(s.out).at("scene.toml").find("gap = 0.0123"), std::string::npos) << "the first run's set";
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
}

TEST(OutputTransaction, StaleTemporariesOfKilledRunsAreRemoved) {
  Scratch s;
  ASSERT_EQ(solve(s.out).code, 0);
  const std::string dead = std::to_string(gone_pid());
  fs::create_directories(s.root / (".out.hemivem-new." + dead));
  std::ofstream(s.root / (".out.hemivem-new." + dead) / "result.json") << "half";
  std::ofstream(s.out / (".solution.vtu.tmp." + dead + ".3")) << "half a file";
  // a live process's temporaries are not touched
  const std::string live = std::to_string(::getppid());
  std::ofstream(s.out / (".solution.vtu.tmp." + live + ".0")) << "being written";
  // nor is a file of another name
  std::ofstream(s.out / (".notes.tmp." + dead + ".1")) << "mine";
  ASSERT_EQ(solve(s.out).code, 0);
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
  EXPECT_FALSE(fs::exists(s.out / (".solution.vtu.tmp." + dead + ".3")));
  EXPECT_TRUE(fs::exists(s.out / (".solution.vtu.tmp." + live + ".0")));
  EXPECT_TRUE(fs::exists(s.out / (".notes.tmp." + dead + ".1")));
}

TEST(OutputTransaction, ReplacesOwnedFilesAndKeepsOtherContent) {
  Scratch s;
  fs::create_directories(s.out);
  std::ofstream(s.out / "notes.txt") << "mine";
  std::ofstream(s.out / "a.csv") << "old a";
  std::ofstream(s.out / "b.png") << "old b";
  {
    OutputTransaction tx(s.out, {"a.csv", "b.png"});
    tx.write("a.csv", [](std::ostream& os) { os << "new a"; });
    EXPECT_EQ(slurp(s.out / "a.csv"), "old a") << "nothing changes before commit";
    EXPECT_EQ(tx.commit(), std::vector<std::string>{"b.png"});
  }
  EXPECT_EQ(contents(s.out), (std::map<std::string, std::string>{{"a.csv", "new a"}, {"notes.txt", "mine"}}));
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
}

TEST(OutputTransaction, ReplacesAFolderOfOwnedFilesAtOnce) {
  Scratch s;
  fs::create_directories(s.out);
  std::ofstream(s.out / "a.csv") << "old a";
  std::ofstream(s.out / "b.png") << "old b";
  {
    OutputTransaction tx(s.out, {"a.csv", "b.png"});
    tx.write("a.csv", [](std::ostream& os) { os << "new a"; });
    EXPECT_EQ(tx.commit(), std::vector<std::string>{"b.png"});
  }
  EXPECT_EQ(contents(s.out), (std::map<std::string, std::string>{{"a.csv", "new a"}}));
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
}

TEST(OutputTransaction, WithoutCommitTheFolderIsUntouched) {
  Scratch s;
  fs::create_directories(s.out);
  std::ofstream(s.out / "a.csv") << "old a";
  try {
    OutputTransaction tx(s.out, {"a.csv"});
    tx.write("a.csv", [](std::ostream& os) { os << "new a"; });
    throw NumericalError("failed after writing");
  } catch (const NumericalError&) {
  }
  EXPECT_EQ(contents(s.out), (std::map<std::string, std::string>{{"a.csv", "old a"}}));
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
}

TEST(OutputTransaction, ACompleteSetOfAKilledRunIsMovedIn) {
  // killed after its set was complete and before it was in place: the next run finishes the move
  Scratch s;
  fs::create_directories(s.out);
  std::ofstream(s.out / "a.csv") << "old a";
  std::ofstream(s.out / "b.png") << "old b";
  std::ofstream(s.out / "notes.txt") << "mine";
  const fs::path ready = s.root / (".out.hemivem-ready." + std::to_string(gone_pid()));
  fs::create_directories(ready);
  std::ofstream(ready / "a.csv") << "new a";
  std::ofstream(ready / ".hemivem-manifest") << "put a.csv\ndrop b.png\n";
  {
    OutputTransaction tx(s.out, {"a.csv", "b.png"});
    EXPECT_EQ(contents(s.out),
              (std::map<std::string, std::string>{{"a.csv", "new a"}, {"notes.txt", "mine"}}));
  }
  EXPECT_EQ(beside(s.root), std::vector<std::string>{});
}

TEST(OutputTransaction, TheLockIsHeldUntilTheTransactionEnds) {
  Scratch s;
  auto tx = std::make_unique<OutputTransaction>(s.out, std::vector<std::string>{"a.csv"});
  // flock locks belong to the open file: a second open in this process is a second writer
  const std::string message = hemivem::test::input_error_of([&] { OutputTransaction second(s.out, {"a.csv"}); });
  EXPECT_NE(message.find("another hemivem run is writing " + s.out.string()), std::string::npos) << message;
  tx.reset();
  EXPECT_NO_THROW(OutputTransaction(s.out, {"a.csv"}));
}

TEST(AtomicFile, AShortWriteIsAnErrorAndLeavesTheFileAsItWas) {
  Scratch s;
  fs::create_directories(s.out);
  std::ofstream(s.out / "a.txt") << "old";
  // in a child process: the hook counts the files a process writes, from its first
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setenv("HEMIVEM_TEST_FAIL_WRITE", "1", 1);
    try {
      write_file_atomically(s.out / "a.txt", [](std::ostream& os) { os << std::string(10000, 'x'); });
    } catch (const WriteError& e) {
      ::_exit(std::string(e.what()).find("No space left on device") != std::string::npos ? 0 : 2);
    }
    ::_exit(1);
  }
  const int status = wait_for(pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: the write succeeded; 2: another message";
  EXPECT_EQ(contents(s.out), (std::map<std::string, std::string>{{"a.txt", "old"}}));
}

// --export-reduced writes its folder as one transaction too: a failed write inside it leaves
// the previous reduced problem, and nothing beside it.
TEST(OutputTransaction, AFailedReducedProblemKeepsThePreviousOne) {
  Scratch s;
  const fs::path reduced = s.root / "reduced";
  ASSERT_EQ(solve(s.out, "", "--export-reduced " + reduced.string()).code, 0);
  const auto before = contents(reduced);
  ASSERT_TRUE(before.count("S.mtx") && before.count("problem.txt"));
  // the reduced problem's files are the first this process writes: the second fails
  const auto run = solve(s.out, "HEMIVEM_TEST_FAIL_WRITE=2", "--export-reduced " + reduced.string() +
                                                                  " --set contact.gap=0.0123");
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.err.find("keeps its previous outputs"), std::string::npos) << run.err;
  EXPECT_EQ(contents(reduced), before);
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(s.root))
    if (e.path().filename() != "out" && e.path().filename() != "reduced") left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{});
  // a later run replaces it whole
  ASSERT_EQ(solve(s.out, "", "--export-reduced " + reduced.string() + " --set contact.gap=0.0123").code, 0);
  EXPECT_NE(contents(reduced).at("g.txt"), before.at("g.txt"));
}
