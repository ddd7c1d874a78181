// Nonconvex problems through the command (docs/nonconvex.md): --global on solve and minimize,
// the search keys of scenes, laws given as j alone, check comparing energies, and the
// delamination scene.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <hemivem/scene/scene.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using hemivem::test::CommandRun;
using hemivem::test::scratch;
using hemivem::test::slurp;
CommandRun run(const std::string& args) { return hemivem::test::run_hemivem(args); }

nlohmann::json result_of(const fs::path& out) { return nlohmann::json::parse(slurp(out / "result.json")); }

const std::string kSawtooth = "--n 6 --set 'contact.law=\"sawtooth\"'";

}  // namespace

TEST(CliNonconvex, SolveGlobalReportsTheCriticalPointsAndTheLowest) {
  const fs::path local = scratch("local"), global = scratch("global");
  const CommandRun l = run("solve " + kSawtooth + " --minimizer bundle-dca -q --out " + local.string());
  ASSERT_EQ(l.code, 0) << l.err;
  const CommandRun g = run("solve " + kSawtooth + " --minimizer bundle-dca --global --out " + global.string());
  ASSERT_EQ(g.code, 0) << g.err;
  EXPECT_NE(g.err.find("hemivem: global search run 1/64: bundle-dca from given"), std::string::npos) << g.err;
  EXPECT_NE(g.out.find("critical pt 1"), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("(lowest: the solution reported)"), std::string::npos) << g.out;

  const auto jl = result_of(local), jg = result_of(global);
  EXPECT_EQ(jl.at("search").at("kind"), "local");
  EXPECT_TRUE(jl.at("critical_points").empty());
  EXPECT_EQ(jg.at("search").at("kind"), "global");
  EXPECT_EQ(jg.at("search").at("engines").at(0), "bundle-dca");
  EXPECT_EQ(jg.at("search").at("max_starts"), 64);
  EXPECT_EQ(jg.at("backends").at("minimizer"), "bundle-dca");
  EXPECT_EQ(jg.at("converged"), true);
  EXPECT_EQ(jg.at("may_be_nonunique"), true);
  const auto& points = jg.at("critical_points");
  ASSERT_GE(points.size(), 2u);
  const double lowest = points.at(0).at("potential_energy").get<double>();
  EXPECT_NEAR(lowest, jg.at("potential_energy").get<double>(), 1e-12 * std::abs(lowest));
  for (std::size_t k = 1; k < points.size(); ++k)
    EXPECT_GE(points.at(k).at("potential_energy").get<double>(), points.at(k - 1).at("potential_energy").get<double>());
  for (const auto& p : points) {
    EXPECT_LE(p.at("certificate").at("primal").get<double>(), 1e-10);
    EXPECT_LE(p.at("certificate").at("dual").get<double>(), 1e-10);
    EXPECT_GE(p.at("starts").get<int>(), 1);
  }
  // bundle-dca alone stops 1.4 % higher on this problem; the search does not
  EXPECT_LT(lowest, jl.at("potential_energy").get<double>() - 1e-6 * std::abs(lowest));
  // the resolved scene repeats the search
  const std::string toml = slurp(global / "scene.toml");
  EXPECT_NE(toml.find("search = \"global\""), std::string::npos);
  EXPECT_NE(toml.find("max_starts = 64"), std::string::npos);
  EXPECT_NE(toml.find("search_engines = []"), std::string::npos);
  // history.csv: one line per local run
  const std::string history = slurp(global / "history.csv");
  EXPECT_GE(std::count(history.begin(), history.end(), '\n'), 10);
}

TEST(CliNonconvex, MinimizeGlobalOnExportedFiles) {
  const fs::path out = scratch("export-out"), reduced = scratch("export-reduced");
  const CommandRun s = run("solve " + kSawtooth + " -q --out " + out.string() + " --export-reduced " + reduced.string());
  ASSERT_EQ(s.code, 0) << s.err;
  const CommandRun g = run("minimize " + reduced.string() + " --global --json");
  ASSERT_EQ(g.code, 0) << g.err;
  const auto j = nlohmann::json::parse(g.out);
  EXPECT_EQ(j.at("search").at("kind"), "global");
  ASSERT_FALSE(j.at("critical_points").empty());
  const double F = j.at("reduced_objective").get<double>();
  EXPECT_EQ(j.at("critical_points").at(0).at("reduced_objective").get<double>(), F);
  EXPECT_NEAR(F, -0.0186541, 5e-7);  // the global minimum by enumeration (test_nonconvex)

  const CommandRun budget = run("minimize " + reduced.string() + " --global --max-starts 2 --seed 7");
  EXPECT_NE(budget.out.find("budget spent"), std::string::npos) << budget.out;
  EXPECT_NE(budget.err.find("run 2/2"), std::string::npos) << budget.err;
  const CommandRun two = run("minimize " + reduced.string() + " --global --engines ceres-active-set,ssn --json");
  ASSERT_EQ(two.code, 0) << two.err;
  const auto jt = nlohmann::json::parse(two.out);
  EXPECT_EQ(jt.at("search").at("engines"), (nlohmann::json{"ssn", "ceres-active-set"}));
  EXPECT_EQ(jt.at("reduced_objective").get<double>(), F);
  const CommandRun unknown = run("minimize " + reduced.string() + " --global --engines ssn,newton");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("unknown minimizer 'newton'"), std::string::npos) << unknown.err;
  const CommandRun zero = run("minimize " + reduced.string() + " --global --max-starts 0");
  EXPECT_EQ(zero.code, 2);
  EXPECT_NE(zero.err.find("--max-starts"), std::string::npos) << zero.err;
}

TEST(CliNonconvex, SceneKeysOfTheSearchAndOfJAlone) {
  auto error_of = [](const std::string& extra) {
    const fs::path f = scratch("scene") .replace_extension(".toml");
    std::ofstream(f) << "schema_version = 1\n" << extra;
    return run("solve " + f.string() + " --n 4 -q --out " + scratch("never").string());
  };
  const CommandRun search = error_of("[solver]\nsearch = \"globl\"\n");
  EXPECT_EQ(search.code, 2);
  EXPECT_NE(search.err.find(":3"), std::string::npos) << search.err;
  EXPECT_NE(search.err.find("did you mean 'global'"), std::string::npos) << search.err;
  const CommandRun starts = error_of("[solver]\nmax_starts = 0\n");
  EXPECT_EQ(starts.code, 2);
  EXPECT_NE(starts.err.find("max_starts"), std::string::npos) << starts.err;
  EXPECT_NE(starts.err.find("must be between 1 and 1000000, got 0"), std::string::npos) << starts.err;
  const CommandRun engines = error_of("[solver]\nsearch_engines = [\"ssn\", \"bundle-dac\"]\n");
  EXPECT_EQ(engines.code, 2);
  EXPECT_NE(engines.err.find(":3"), std::string::npos) << engines.err;
  EXPECT_NE(engines.err.find("unknown minimizer 'bundle-dac'; did you mean 'bundle-dca'?"), std::string::npos)
      << engines.err;
  const CommandRun budget = error_of("[solver]\ntime_budget = -1\n");
  EXPECT_EQ(budget.code, 2);
  EXPECT_NE(budget.err.find("time_budget"), std::string::npos) << budget.err;

  const std::string piecewise = "[contact]\nside = \"bottom\"\nlaw = \"piecewise\"\nbreakpoints = [0.0]\n";
  const CommandRun both = error_of(piecewise + "j = [[0.0], [0.0, 0.0, 1.0]]\nj1 = [[0.0], [0.0, 0.0, 1.0]]\nj2 = [[0.0], [0.0]]\n");
  EXPECT_EQ(both.code, 2);
  EXPECT_NE(both.err.find("give either j alone"), std::string::npos) << both.err;
  const CommandRun jump = error_of(piecewise + "j = [[0.0], [1.0, 0.0, 1.0]]\n");
  EXPECT_EQ(jump.code, 2);
  EXPECT_NE(jump.err.find(":6"), std::string::npos) << jump.err;  // the line of j
  EXPECT_NE(jump.err.find("j is not continuous at breakpoint 0"), std::string::npos) << jump.err;

  // j alone (set on the command line): the same solution as the paper's law (4.7) with its split (4.8)
  const fs::path a = scratch("paper-j-out"), b = scratch("paper-out");
  const CommandRun with_j = run("solve --n 16 -q --out " + a.string() +
                                " --set 'contact.law=\"piecewise\"' --set 'contact.breakpoints=[0.0, 0.01, 0.02]'"
                                " --set 'contact.j=[[0.0], [0.0, 0.0, 30.0], [-0.004, 0.8, -10.0], [0.012, -0.8, 30.0]]'");
  ASSERT_EQ(with_j.code, 0) << with_j.err;
  ASSERT_EQ(run("solve --n 16 -q --out " + b.string()).code, 0);
  const auto ja = result_of(a), jb = result_of(b);
  EXPECT_NEAR(ja.at("potential_energy").get<double>(), jb.at("potential_energy").get<double>(),
              1e-12 * std::abs(jb.at("potential_energy").get<double>()));
  EXPECT_NE(slurp(a / "scene.toml").find("j = [[0.0], [0.0, 0.0, 30.0], [-0.004, 0.8, -10.0], [0.012, -0.8, 30.0]]"),
            std::string::npos)
      << slurp(a / "scene.toml");
  EXPECT_EQ(ja.at("uniqueness_margin").get<double>(), jb.at("uniqueness_margin").get<double>());
}

TEST(CliNonconvex, CheckComparesEnergiesAndNamesTheLowestPair) {
  const CommandRun r = run("check " + kSawtooth + " --json");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("unique"), false);
  ASSERT_TRUE(j.at("lowest_energy").is_object());
  const double lowest = j.at("lowest_energy").at("potential_energy").get<double>();
  for (const auto& p : j.at("pairs"))
    if (p.at("converged") == true) EXPECT_GE(p.at("potential_energy").get<double>(), lowest);
  EXPECT_NE(j.at("verdict").get<std::string>().find("the lowest energy"), std::string::npos) << j.at("verdict");
  // pairs reaching the same point to round-off tie: the first in table order is named
  EXPECT_EQ(j.at("lowest_energy").at("linear"), "eigen");
  EXPECT_EQ(j.at("lowest_energy").at("minimizer"), "ssn");
  EXPECT_GE(j.at("lowest_energy").at("pairs_at_lowest").get<int>(), 2);
  EXPECT_GE(j.at("lowest_energy").at("pairs_higher").get<int>(), 1);
  // bundle-dca stops at another critical point: differences are reported, not a failure
  EXPECT_GT(j.at("lowest_energy").at("highest_converged").get<double>(), lowest);
  const CommandRun text = run("check " + kSawtooth);
  EXPECT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("(lowest)"), std::string::npos) << text.out;
}

TEST(CliNonconvex, DelaminationScene) {
  const fs::path out = scratch("delamination");
  const CommandRun r = run("solve " + (hemivem::test::scenes_dir() / "delamination.toml").string() +
                           " --set 'mesh.n=[32, 4]' --set solver.max_starts=12 -q --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = result_of(out);
  EXPECT_EQ(j.at("converged"), true);
  EXPECT_EQ(j.at("may_be_nonunique"), true);
  EXPECT_EQ(j.at("uniqueness_margin"), nullptr);  // -infinity: three concave kinks
  EXPECT_EQ(j.at("search").at("kind"), "global");
  ASSERT_FALSE(j.at("critical_points").empty());
  // pulled up: the bottom separates (u_nu = -u_y < 0) and the binding force is the law's
  int separated = 0;
  for (const auto& n : j.at("contact")) separated += n.at("u_nu").get<double>() < 0.0;
  EXPECT_GT(separated, 20);
  // the resolved scene keeps j alone and reproduces the run
  const std::string toml = slurp(out / "scene.toml");
  EXPECT_NE(toml.find("j = [[40000.0], [10000.0, -5e+06, 5e+09], [0.0, -1e+07, 1e+10], [0.0, 0.0, 3e+10], [0.0]]"),
            std::string::npos)
      << toml;
  const fs::path again = scratch("delamination-again");
  ASSERT_EQ(run("solve " + (out / "scene.toml").string() + " -q --out " + again.string()).code, 0);
  EXPECT_EQ(result_of(again).at("potential_energy"), j.at("potential_energy"));
}
