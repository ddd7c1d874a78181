// The command's side of the claims of test_claims.cpp: result.json's uniqueness fields, a
// reduced problem's margin recomputed for another law and checked when given, the tolerance
// flags, and the warning of a solve whose displacement has unreliable digits.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/scene/scene.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace hemivem;

namespace {

test::CommandRun run(const std::string& args) { return test::run_hemivem(args); }

const fs::path kSliver = test::data_dir() / "claims" / "near-coincident-columns.poly2d";

}  // namespace

TEST(CliClaims, ResultJsonAndSummarySayWhatAZeroMarginMeans) {
  ContactSolution sol;
  sol.status = MinimizerStatus::converged;
  sol.uniqueness_margin = 0.0;
  sol.uniqueness_roundoff = 3e-13;
  sol.may_be_nonunique = true;
  const Mesh mesh = make_squares(2);
  const nlohmann::json j = app::result_json(mesh, sol, app::RunInfo{});
  EXPECT_EQ(j.at("uniqueness"), "zero");
  EXPECT_EQ(j.at("uniqueness_margin").get<double>(), 0.0);
  EXPECT_EQ(j.at("uniqueness_roundoff").get<double>(), 3e-13);
}


// ---- 5. a badly conditioned mesh is warned about -------------------------------------------

TEST(CliClaims, SolveWarnsWhenTheDisplacementsDigitsAreUnreliable) {
  Scene s = default_scene();
  s.mesh.file = kSliver;
  s.solver.linear = "eigen";
  const app::SceneSolve bad = app::solve_scene(s);
  ASSERT_TRUE(bad.solution.converged()) << bad.solution.message;
  ASSERT_TRUE(std::isfinite(bad.solution.condition_estimate));
  EXPECT_GE(bad.solution.condition_estimate, app::unreliable_condition);
  ASSERT_EQ(bad.warnings.size(), bad.built->warnings.size() + 1);
  EXPECT_NE(bad.warnings.back().find("condition number"), std::string::npos) << bad.warnings.back();
  const app::RunInfo info = app::run_info(s, bad);
  EXPECT_EQ(info.warnings, bad.warnings);
  const nlohmann::json j = app::result_json(bad.built->mesh, bad.solution, info);
  EXPECT_NE(j.at("warnings").back().get<std::string>().find("condition number"), std::string::npos);
  EXPECT_GE(j.at("condition_estimate").get<double>(), app::unreliable_condition);

  // the same square without the sliver column: no warning, and a modest estimate
  Scene good = default_scene();
  good.mesh.n = 8;
  good.solver.linear = "eigen";
  const app::SceneSolve fine = app::solve_scene(good);
  ASSERT_TRUE(fine.solution.converged());
  EXPECT_LT(fine.solution.condition_estimate, 1e6);
  EXPECT_EQ(fine.warnings, fine.built->warnings);
  EXPECT_TRUE(app::conditioning_warning(std::numeric_limits<double>::quiet_NaN()).empty());
}

TEST(CliClaims, ABodyHeldOnlyByItsContactIsNotCalledUnique) {
  const fs::path scene = test::data_dir() / "claims" / "block-between-rollers.toml";
  for (const char* E : {"65", "100"}) {
    const fs::path out = test::scratch(std::string("claims-block-") + E);
    const test::CommandRun r = run("solve " + scene.string() + " --set material.E=" + E + " --out " + out.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("lambda_min(S - alpha_j W) = 0 (|computed| <= round-off bound"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("not strongly convex along some direction, so uniqueness is not proved"), std::string::npos);
    EXPECT_EQ(r.out.find("unique\n"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(test::slurp(out / "result.json"));
    EXPECT_EQ(j.at("uniqueness_margin").get<double>(), 0.0);
    EXPECT_EQ(j.at("uniqueness"), "zero");
    EXPECT_GT(j.at("uniqueness_roundoff").get<double>(), 0.0);
    EXPECT_LT(j.at("uniqueness_roundoff").get<double>(), 1e-10);
    EXPECT_EQ(j.at("may_be_nonunique"), true);
  }
}

TEST(CliClaims, MinimizeWithAnotherLawRecomputesTheMargin) {
  const fs::path dir = test::scratch("claims-export");
  const test::CommandRun e = run("solve --n 4 -q --out " + test::scratch("claims-export-out").string() +
                                 " --export-reduced " + dir.string());
  ASSERT_EQ(e.code, 0) << e.err;
  ASSERT_GT(read_reduced_problem(dir).uniqueness_margin, 0.0);  // the paper's law
  const test::CommandRun r = run("minimize " + dir.string() + " --law sawtooth --global --max-starts 4 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("may_be_nonunique"), true);
  EXPECT_EQ(j.at("search").at("kind"), "global");
  EXPECT_EQ(j.at("law"), "sawtooth");
}

TEST(CliClaims, MinimizeRefusesAMarginThatIsNotTheProblems) {
  // S = -I: F is concave; a stored margin of 1 would make a maximum "converged and unique"
  ReducedProblem p = ReducedProblem::uniform(-Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2),
                                             Eigen::VectorXd::Ones(2), make_contact_law("zero"), ConstraintKind::none);
  p.uniqueness_margin = 1.0;
  const fs::path dir = test::scratch("claims-concave");
  write_reduced_problem(dir, p);
  const test::CommandRun r = run("minimize " + dir.string() + " --json");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.err.find((dir / "problem.txt").string() + ":"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("uniqueness_margin 1 is not the margin of this problem"), std::string::npos) << r.err;
}

TEST(CliClaims, ToleranceFlagsAreChecked) {
  const std::string out = " --out " + test::scratch("claims-tol").string();
  for (const std::string& tol : {"0.5", "0.999", "1e300", "0.0100001"}) {
    const test::CommandRun s = run("solve --n 4 --tol " + tol + out);
    EXPECT_EQ(s.code, 2) << tol;
    EXPECT_NE(s.err.find("--tol: must be in [1e-300, 0.01], got"), std::string::npos) << s.err;
    EXPECT_EQ(s.err.find("--set"), std::string::npos) << s.err;
  }
  const test::CommandRun m = run("minimize . --tol 0.5");
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.err.find("--tol: must be in [1e-300, 0.01], got 0.5"), std::string::npos) << m.err;
  const test::CommandRun k = run("solve --n 4 --set solver.tolerance=0.75" + out);
  EXPECT_EQ(k.code, 2);
  EXPECT_NE(k.err.find("solver.tolerance: must be in [1e-300, 0.01], got 0.75"), std::string::npos) << k.err;
  EXPECT_EQ(run("solve --n 4 -q --tol 1e-2" + out).code, 0);
}

TEST(CliClaims, SolveOnASliverMeshWarns) {
  const fs::path out = test::scratch("claims-sliver");
  const test::CommandRun r = run("solve --mesh " + kSliver.string() + " --linear eigen -q --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("hemivem: warning: the estimated condition number of the factorized matrix is"),
            std::string::npos)
      << r.err;
  const auto j = nlohmann::json::parse(test::slurp(out / "result.json"));
  ASSERT_FALSE(j.at("warnings").empty());
  EXPECT_NE(j.at("warnings").back().get<std::string>().find("condition number"), std::string::npos);
}
