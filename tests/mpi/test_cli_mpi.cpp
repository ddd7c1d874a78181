// The hemivem command under mpiexec (docs/cluster.md): `solve --linear mumps-mpi` on two
// processes agrees with `--linear eigen` on one, rank 0 alone prints and writes, and what may
// not run across processes is refused.
//
// "Rank 0 alone writes" is observed directly: mpiexec starts the two ranks with different
// --out folders (MPMD, `-n 1 A : -n 1 B`), everything else on their command lines equal, and
// rank 1's folder must not appear.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "command_mpi.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

using namespace hemivem::test::mpi;  // run, mpiexec, np, binary, count, CommandRun, slurp

fs::path scratch(const std::string& name) { return hemivem::test::mpi::scratch("cli", name); }

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

TEST(CliMpi, TwoProcessesAgreeWithEigenAndRankZeroAloneWrites) {
  const std::string scene = " solve --n 16 --tol 1e-11";
  const fs::path ref = scratch("eigen"), out0 = scratch("rank0"), out1 = scratch("rank1");
  const CommandRun e = run(binary() + scene + " --linear eigen -q --out " + ref.string());
  ASSERT_EQ(e.code, 0) << e.err;

  const CommandRun m = run(mpiexec() + " " + np(1) + " " + binary() + scene + " --linear mumps-mpi --out " + out0.string() +
                    " : " + np(1) + " " + binary() + scene + " --linear mumps-mpi --out " + out1.string());
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  EXPECT_EQ(count(m.out, "hemivem solve:"), 1u) << m.out;
  EXPECT_EQ(count(m.out, "linear mumps-mpi (2 processes)"), 1u) << m.out;
  EXPECT_EQ(count(m.err, "solving with mumps-mpi"), 1u) << m.err;
  EXPECT_FALSE(fs::exists(out1)) << "rank 1 wrote outputs";

  const nlohmann::json a = read_json(out0 / "result.json"), b = read_json(ref / "result.json");
  EXPECT_EQ(a["processes"], 2);
  EXPECT_EQ(b["processes"], 1);
  EXPECT_EQ(a["backends"]["linear"], "mumps-mpi");
  EXPECT_TRUE(a["converged"].get<bool>());
  EXPECT_EQ(a["stages"], b["stages"]);
  const double ea = a["potential_energy"].get<double>(), eb = b["potential_energy"].get<double>();
  EXPECT_NEAR(ea, eb, 1e-10 * std::abs(eb));
  EXPECT_NEAR(a["uniqueness_margin"].get<double>(), b["uniqueness_margin"].get<double>(),
              1e-8 * b["uniqueness_margin"].get<double>());
  ASSERT_EQ(a["contact"].size(), 15u);
  ASSERT_EQ(a["contact"].size(), b["contact"].size());
  for (std::size_t i = 0; i < a["contact"].size(); ++i) {
    const auto& x = a["contact"][i];
    const auto& y = b["contact"][i];
    EXPECT_EQ(x["vertex"], y["vertex"]);
    EXPECT_EQ(x["state"], y["state"]);
    EXPECT_NEAR(x["u_nu"].get<double>(), y["u_nu"].get<double>(), 1e-12) << "node " << i;
  }
  for (const char* f : {"result.json", "contact.csv", "displacement.csv", "history.csv", "solution.vtu", "scene.toml"})
    EXPECT_TRUE(fs::exists(out0 / f)) << f;
  // displacement.csv: every value equal to 1e-10 of the largest displacement
  std::istringstream da(slurp(out0 / "displacement.csv")), db(slurp(ref / "displacement.csv"));
  std::string la, lb;
  std::getline(da, la);
  std::getline(db, lb);
  ASSERT_EQ(la, lb);
  double largest = 0.0, diff = 0.0;
  int rows = 0;
  while (std::getline(db, lb)) {
    ASSERT_TRUE(std::getline(da, la));
    double va[5], vb[5];
    ASSERT_EQ(std::sscanf(la.c_str(), "%lf,%lf,%lf,%lf,%lf", &va[0], &va[1], &va[2], &va[3], &va[4]), 5) << la;
    ASSERT_EQ(std::sscanf(lb.c_str(), "%lf,%lf,%lf,%lf,%lf", &vb[0], &vb[1], &vb[2], &vb[3], &vb[4]), 5) << lb;
    for (int k = 3; k < 5; ++k) {
      largest = std::max(largest, std::abs(vb[k]));
      diff = std::max(diff, std::abs(va[k] - vb[k]));
    }
    ++rows;
  }
  EXPECT_EQ(rows, 17 * 17);
  EXPECT_GT(largest, 0.0);
  EXPECT_LE(diff, 1e-10 * largest);
}

// A three-dimensional scene across two processes: the same solution as eigen on one.
TEST(CliMpi, ThreeDimensionalSceneOnTwoProcessesAgreesWithEigen) {
  const std::string scene = std::string(" solve ") + HEMIVEM_SOURCE_DIR + "/scenes/example-4.1-3d.toml --tol 1e-11";
  const fs::path ref = scratch("eigen3d"), out = scratch("mpi3d");
  const CommandRun e = run(binary() + scene + " --linear eigen -q --out " + ref.string());
  ASSERT_EQ(e.code, 0) << e.err;
  const CommandRun m = run(mpiexec() + " " + np(2) + " " + binary() + scene + " --linear mumps-mpi -q --out " + out.string());
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  const nlohmann::json a = read_json(out / "result.json"), b = read_json(ref / "result.json");
  EXPECT_EQ(a["dimension"], 3);
  EXPECT_EQ(a["processes"], 2);
  EXPECT_TRUE(a["converged"].get<bool>());
  ASSERT_EQ(a["contact"].size(), b["contact"].size());
  ASSERT_GT(a["contact"].size(), 0u);
  for (std::size_t i = 0; i < a["contact"].size(); ++i) {
    EXPECT_EQ(a["contact"][i]["state"], b["contact"][i]["state"]);
    EXPECT_NEAR(a["contact"][i]["u_nu"].get<double>(), b["contact"][i]["u_nu"].get<double>(), 1e-12) << "node " << i;
  }
  EXPECT_NEAR(a["potential_energy"].get<double>(), b["potential_energy"].get<double>(),
              1e-10 * std::abs(b["potential_energy"].get<double>()));
}

TEST(CliMpi, EveryRankExitsWithTheSameCode) {
  // Each rank records its own exit code; the solve stops after one iteration: exit 3 everywhere.
  const fs::path dir = scratch("codes");
  fs::create_directories(dir);
  const std::string solve = binary() + " solve --n 8 --linear mumps-mpi --set solver.max_iterations=1 --tol 1e-14 -q --out " +
                            (dir / "out").string();
  auto ranked = [&](int r) {
    return np(1) + " sh -c '" + solve + "; echo $? > " + (dir / ("code" + std::to_string(r))).string() + "'";
  };
  const CommandRun m = run(mpiexec() + " " + ranked(0) + " : " + ranked(1));
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(slurp(dir / "code0"), "3\n");
  EXPECT_EQ(slurp(dir / "code1"), "3\n");
  EXPECT_FALSE(read_json(dir / "out" / "result.json")["converged"].get<bool>());
}

TEST(CliMpi, AnInputErrorAfterTheEngineExistsIsReportedOnceAndNobodyHangs) {
  // The engine is created before the mesh is read: every rank fails on the missing file.
  const fs::path out = scratch("missing");
  const CommandRun m = run(mpiexec() + " " + np(2) + " " + binary() + " solve --linear mumps-mpi --mesh /nonexistent/mesh.poly2d --out " +
                    out.string());
  EXPECT_EQ(m.code, 2) << m.err;
  EXPECT_EQ(count(m.err, "hemivem: error:"), 1u) << m.err;
  EXPECT_NE(m.err.find("nonexistent/mesh.poly2d"), std::string::npos) << m.err;
  EXPECT_FALSE(fs::exists(out));
}

// every process of mumps-mpi builds and assembles the whole problem: a limit above one
// process's estimate (37 MiB) and below two's refuses two processes, before anything is written
TEST(CliMpi, TheMemoryCheckCountsEveryProcessHoldingTheWholeProblem) {
  const std::string limit = "env HEMIVEM_MEMORY_LIMIT=55M ";
  const fs::path one = scratch("memory-one"), two = scratch("memory-two");
  const CommandRun a = run(limit + binary() + " solve --n 64 --linear mumps-mpi -q --out " + one.string());
  EXPECT_EQ(a.code, 0) << a.err;
  const CommandRun m =
      run(limit + mpiexec() + " " + np(2) + " " + binary() + " solve --n 64 --linear mumps-mpi -q --out " + two.string());
  EXPECT_EQ(m.code, 2) << m.err;
  EXPECT_EQ(count(m.err, "hemivem: error:"), 1u) << m.err;
  EXPECT_EQ(count(m.err, "needs an estimated 73 MiB of memory across 2 processes (37 MiB in one process)"), 1u) << m.err;
  EXPECT_FALSE(fs::exists(two));
}

TEST(CliMpi, AnotherEngineOnSeveralProcessesIsRefused) {
  const fs::path out = scratch("refused");
  const CommandRun m = run(mpiexec() + " " + np(2) + " " + binary() + " solve --n 8 --linear eigen --out " + out.string());
  EXPECT_EQ(m.code, 2);
  EXPECT_EQ(count(m.err, "hemivem: error:"), 1u) << m.err;
  EXPECT_NE(m.err.find("use --linear mumps-mpi"), std::string::npos) << m.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(m.out.empty()) << m.out;
}

TEST(CliMpi, OtherCommandsAreRefusedOnSeveralProcesses) {
  const fs::path bench = scratch("bench"), study = scratch("study");
  for (const std::string& cmd : std::vector<std::string>{"check --n 4", "bench --n 4 --ref 8 --out " + bench.string(),
                                "study --n 4 --ref 8 --out " + study.string()}) {
    const CommandRun m = run(mpiexec() + " " + np(2) + " " + binary() + " " + cmd);
    EXPECT_EQ(m.code, 2) << cmd;
    EXPECT_EQ(count(m.err, "only 'hemivem solve' runs across processes"), 1u) << cmd << ": " << m.err;
  }
  EXPECT_FALSE(fs::exists(bench));
  EXPECT_FALSE(fs::exists(study));
}

TEST(CliMpi, OneProcessUnderMpiexecIsAnOrdinaryRun) {
  const fs::path out = scratch("one");
  const CommandRun m = run(mpiexec() + " " + np(1) + " " + binary() + " solve --n 8 --linear eigen -q --out " + out.string());
  EXPECT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(read_json(out / "result.json")["processes"], 1);
}

}  // namespace
