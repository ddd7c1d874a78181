// The threads of OpenBLAS and OpenMP around a run (hemivem/support/blas_threads.hpp): one each
// while a guard is alive, the counts of before once it is gone, the count the environment asks
// for left alone; app::run_scene runs inside such a guard.
#include <gtest/gtest.h>

#include <hemivem/app/run.hpp>
#include <hemivem/support/blas_threads.hpp>

#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <dlfcn.h>

namespace hemivem {
namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

template <class F>
F symbol(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_DEFAULT, name));
}

/// OpenBLAS's and OpenMP's thread counts, as this program sees them.
struct Counts {
  GetThreads blas_get = symbol<GetThreads>("openblas_get_num_threads");
  SetThreads blas_set = symbol<SetThreads>("openblas_set_num_threads");
  GetThreads omp_get = symbol<GetThreads>("omp_get_max_threads");
  SetThreads omp_set = symbol<SetThreads>("omp_set_num_threads");

  /// Why a test cannot run here, or empty.
  std::string missing() const {
    if (!blas_get || !blas_set) return "OpenBLAS is not the BLAS loaded (no openblas_get_num_threads)";
    if (!omp_get || !omp_set) return "no OpenMP runtime is loaded (no omp_get_max_threads)";
    return {};
  }
  int blas() const { return blas_get(); }
  int omp() const { return omp_get(); }
};

/// Sets (value) or unsets (nullopt) an environment variable while alive; the value of before after.
class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) before_ = old;
    if (value) {
      setenv(name, value->c_str(), 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnvironment() {
    if (before_) {
      setenv(name_, before_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  const char* name_;
  std::optional<std::string> before_;
};

/// Two threads in OpenBLAS and OpenMP, neither asked for by the environment.
class Threads : public testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = counts_.missing(); !why.empty()) GTEST_SKIP() << why;
    counts_.blas_set(2);
    counts_.omp_set(2);
    if (counts_.blas() != 2) GTEST_SKIP() << "OpenBLAS runs at most " << counts_.blas() << " thread(s) here";
    ASSERT_EQ(counts_.omp(), 2);
  }

  Counts counts_;
  ScopedEnvironment omp_{"OMP_NUM_THREADS", std::nullopt};
  ScopedEnvironment openblas_{"OPENBLAS_NUM_THREADS", std::nullopt};
};

TEST_F(Threads, ARunIsSingleThreadedAndRestoresTheCounts) {
  {
    const SingleThreadedRun one_thread;
    EXPECT_EQ(counts_.blas(), 1);
    EXPECT_EQ(counts_.omp(), 1);
  }
  EXPECT_EQ(counts_.blas(), 2);
  EXPECT_EQ(counts_.omp(), 2);
}

TEST_F(Threads, GuardsMayOverlapTheLastRestores) {
  {
    std::optional<SingleThreadedRun> run;
    run.emplace();
    {
      const SingleThreadedBlas inner;
      EXPECT_EQ(counts_.blas(), 1);
    }
    EXPECT_EQ(counts_.blas(), 1);  // the run still holds it
    auto second = std::make_unique<SingleThreadedBlas>();
    run.reset();
    EXPECT_EQ(counts_.blas(), 1);  // `second` still holds it
    EXPECT_EQ(counts_.omp(), 2);
    second.reset();
  }
  EXPECT_EQ(counts_.blas(), 2);
}

TEST_F(Threads, OmpNumThreadsInTheEnvironmentLeavesOpenMPAlone) {
  const ScopedEnvironment asked("OMP_NUM_THREADS", "2");
  {
    const SingleThreadedRun one_thread;
    EXPECT_EQ(counts_.omp(), 2);
    EXPECT_EQ(counts_.blas(), 1);
  }
  EXPECT_EQ(counts_.omp(), 2);
  EXPECT_EQ(counts_.blas(), 2);
}

TEST_F(Threads, OpenblasNumThreadsInTheEnvironmentLeavesOpenBLASAlone) {
  const ScopedEnvironment asked("OPENBLAS_NUM_THREADS", "2");
  {
    const SingleThreadedRun one_thread;
    EXPECT_EQ(counts_.blas(), 2);
    EXPECT_EQ(counts_.omp(), 1);
  }
  EXPECT_EQ(counts_.omp(), 2);
  EXPECT_EQ(counts_.blas(), 2);
}

TEST_F(Threads, RunSceneSolvesOnOneThreadAndRestoresTheCounts) {
  for (const char* kind : {"static", "path"}) {
    SCOPED_TRACE(kind);
    Scene scene = default_scene();
    apply_overrides(scene, {"mesh.n=8"});
    if (std::string(kind) == "path") apply_overrides(scene, {"path.steps=2"});
    app::RunOptions options;
    int blas_inside = 0;
    int omp_inside = 0;
    options.on_built = [&](const app::BuiltSummary&) {
      blas_inside = counts_.blas();
      omp_inside = counts_.omp();
    };
    const app::SceneRun run = app::run_scene(scene, std::move(options));
    EXPECT_TRUE(run.converged());
    EXPECT_EQ(blas_inside, 1);
    EXPECT_EQ(omp_inside, 1);
    EXPECT_EQ(counts_.blas(), 2);
    EXPECT_EQ(counts_.omp(), 2);
  }
}

}  // namespace
}  // namespace hemivem
