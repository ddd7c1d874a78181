// Messages of the command for mistakes a new user makes: each names the flag or key that was
// given, once, and says what was expected.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <hemivem/app/solve.hpp>
#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace {

using hemivem::test::run_hemivem;
using hemivem::test::scratch;

void expect_error(const std::string& args, const std::string& fragment) {
  const auto out = scratch("cli_messages");
  const auto r = run_hemivem("solve " + args + " --out " + out.string());
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(fragment), std::string::npos) << args << "\n" << r.err;
  EXPECT_FALSE(std::filesystem::exists(out)) << args;
}

TEST(CliMessages, CellCountsSayAnIntegerIsExpected) {
  expect_error("--n abc", "--n: expected an integer, got 'abc'");
  expect_error("--n 0", "--n: must be in [1, 10000000], got 0");
}

TEST(CliMessages, FlagsAreBlamedByTheirOwnName) {
  const auto r = run_hemivem("solve --tol 2 --n 2 --out " + scratch("cli_tol").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: --tol: "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("--set solver.tolerance"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("solver.tolerance: solver.tolerance"), std::string::npos) << r.err;
}

TEST(CliMessages, ContradictoryMeshFlagsAreRefused) {
  expect_error("--mesh squares --set mesh.file=x.msh", "--mesh: not used with mesh.file");
  expect_error("--set mesh.n=8 --set mesh.file=x.msh", "--set mesh.n: not used with mesh.file");
}

TEST(CliMessages, NumbersOutOfRangeAndLawParameters) {
  expect_error("--set contact.gap=1e400", "--set contact.gap: 1e400 is out of the range of a number");
  expect_error("--set contact.law=kinked --set contact.parameters.sigma=-1",
               "--set contact.parameters.sigma: needs finite sigma >= 0 and stiffness >= 0, got sigma -1");
}

TEST(CliMessages, AnUnwritableOutputFolderIsRefusedBeforeTheSolve) {
  if (!std::filesystem::is_directory("/sys/kernel")) GTEST_SKIP() << "no /sys/kernel";
  const auto r = run_hemivem("solve --n 2 --out /sys/kernel");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("/sys/kernel: cannot write into the output folder"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("solving with"), std::string::npos) << r.err;
}

TEST(CliMessages, MeshHelpShowsThePolygonAsPairs) {
  const auto r = run_hemivem("mesh --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--polygon X Y ..."), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("FLOAT x 6"), std::string::npos) << r.out;
}

TEST(CliMessages, RemovingAKeyReplacesAGapByAnObstacle) {
  const auto out = scratch("cli_unset");
  const auto r = run_hemivem("solve --n 4 -q --set contact.gap= --set contact.obstacle.shape=plane "
                             "--set 'contact.obstacle.point=[0.5, -0.01]' --set 'contact.obstacle.normal=[0, 1]' --out " +
                             out.string());
  EXPECT_EQ(r.code, 0) << r.err;
  std::filesystem::remove_all(out);
}

}  // namespace

namespace hemivem {
namespace {

using test::input_error_of;

TEST(SolveBilateral, NoGapIsReportedWhereNoneIsUsed) {
  const Scene plain = parse_scene_string(
      "schema_version = 1\n[mesh]\nn = 4\n[clamped]\nside = [\"left\", \"right\"]\n[[loads.traction]]\nside = \"top\"\n"
      "value = [1, -1]\n[contact]\nside = \"bottom\"\nconstraint = \"bilateral\"\ngap = 0.05\n",
      "b.toml");
  const app::SceneSolve solved = app::solve_scene(plain, {}, {}, nullptr, {});
  ASSERT_FALSE(solved.solution.contact.empty());
  for (const auto& n : solved.solution.contact) EXPECT_TRUE(std::isnan(n.gap)) << n.vertex;
  // the files: an empty gap in contact.csv, null in result.json
  const auto dir = test::scratch("bilateral_files");
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "b.toml") << to_toml(plain); }
  const auto r = test::run_hemivem("solve " + (dir / "b.toml").string() + " -q --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = test::slurp(dir / "out" / "contact.csv");
  EXPECT_NE(csv.find(",tied,,"), std::string::npos) << csv.substr(0, 300);
  EXPECT_EQ(csv.find("0.05"), std::string::npos);
  const std::string json = test::slurp(dir / "out" / "result.json");
  EXPECT_NE(json.find("\"gap\": null"), std::string::npos);
  EXPECT_EQ(json.find("\"gap\": 0.05"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(SolveEngineNames, AnUnknownMinimizerInTheFileNamesItsLine) {
  const Scene s = parse_scene_string("schema_version = 1\n[mesh]\nn = 2\n[clamped]\nside = \"left\"\n[solver]\n"
                                     "minimizer = \"newton\"\n",
                                     "engines.toml");
  const std::string m = input_error_of([&] { (void)app::solve_scene(s, {}, {}, nullptr, {}); });
  EXPECT_NE(m.find("engines.toml:7: solver.minimizer"), std::string::npos) << m;
}

TEST(SolveContactConflicts, ASupportHoldingTheNormalOfAContactNodeTakesItOutOfTheContact) {
  // uy = 0 on the left side holds the corner (0, 0) along the bottom's normal: the support
  // holds it, the contact keeps the other nodes
  const Scene s = parse_scene_string(
      "schema_version = 1\n[mesh]\nn = 4\n[[dirichlet]]\nside = \"left\"\nuy = 0.0\n[[dirichlet]]\nside = \"right\"\n"
      "value = [0, 0]\n[[loads.traction]]\nside = \"top\"\nvalue = [0, -1]\n[contact]\nside = \"bottom\"\n"
      "law = \"linear\"\n",
      "roller.toml");
  const app::SceneSolve solved = app::solve_scene(s, {}, {}, nullptr, {});
  ASSERT_TRUE(solved.solution.converged());
  EXPECT_EQ(solved.solution.contact.size(), 3u);  // the bottom's five nodes less both corners
  for (const auto& n : solved.solution.contact) EXPECT_GT(n.x.x(), 0.0) << n.vertex;
  EXPECT_LT(solved.solution.forces.sum().norm(), 1e-10 * solved.solution.forces.applied.norm());
}

// the shipped Example 4.1 with a roller added: replacing the array of [[dirichlet]] is reported
std::filesystem::path scene_with_roller(const std::string& name) {
  const auto dir = scratch(name);
  std::filesystem::create_directories(dir);
  const auto file = dir / "roller.toml";
  std::ofstream(file) << test::slurp(test::scenes_dir() / "paper-example-4.1.toml")
                      << "\n[[dirichlet]]\nside = \"left\"\nux = 0.0\n";
  return file;
}

TEST(CliMessages, ReplacingAnArrayOfTablesIsAWarningOnStderrAndInResultJson) {
  const auto scene = scene_with_roller("cli_replace_array");
  const auto out = scratch("cli_replace_array_out");
  const auto r = run_hemivem("solve " + scene.string() + " --n 4 --set 'dirichlet=[{side=\"right\", uy=0}]' --out " +
                             out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string notice =
      "--set dirichlet replaced the whole array [[dirichlet]]: its 1 table by 1 (to add one table instead: --set "
      "'dirichlet[+]={...}')";
  EXPECT_NE(r.err.find("hemivem: warning: " + notice), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(test::slurp(out / "result.json"));
  const auto& w = j.at("warnings");
  EXPECT_NE(std::find(w.begin(), w.end(), notice), w.end()) << w.dump();
  const Scene resolved = parse_scene(out / "scene.toml");  // the scene solved, as written
  ASSERT_EQ(resolved.dirichlet.size(), 1u);
  EXPECT_EQ(resolved.dirichlet[0].boundary.sides, std::vector<std::string>{"right"});
}

TEST(CliMessages, AppendingATableKeepsTheScenesOwn) {
  const auto scene = scene_with_roller("cli_append_array");
  const auto out = scratch("cli_append_array_out");
  const auto r = run_hemivem("solve " + scene.string() + " --n 4 --set 'dirichlet[+]={side=\"right\", uy=0}' --out " +
                             out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("replaced"), std::string::npos) << r.err;
  const Scene resolved = parse_scene(out / "scene.toml");
  ASSERT_EQ(resolved.dirichlet.size(), 2u);
  EXPECT_EQ(resolved.dirichlet[0].boundary.sides, std::vector<std::string>{"left"});  // the file's roller
  EXPECT_EQ(resolved.dirichlet[1].boundary.sides, std::vector<std::string>{"right"});
}

}  // namespace
}  // namespace hemivem
