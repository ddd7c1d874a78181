// The check, the study and the bench of hemivem::app (app/check.hpp, app/study.hpp,
// app/bench.hpp) on tiny problems, each against something computed another way: the same
// solve through app::run_scene, the study's error recomputed from two solves, Aitken's
// extrapolation of a geometric sequence, and a mesh compared with itself.
#include <gtest/gtest.h>

#include <hemivem/app/bench.hpp>
#include <hemivem/app/check.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/app/study.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/vem/bilinear.hpp>

#include <cmath>
#include <string>

#include "test_support.hpp"

namespace hemivem::app {
namespace {

Scene small_plane(int n) {
  Scene s = default_scene();
  apply_overrides(s, {"mesh.n=" + std::to_string(n)});
  return s;
}

/// The solve of `scene` with the given engines, through the one entry point.
SceneRun solve_with(Scene scene, const std::string& linear, const std::string& minimizer) {
  apply_overrides(scene, {"solver.linear=\"" + linear + "\"", "solver.minimizer=\"" + minimizer + "\""});
  return run_scene(scene);
}

double max_abs_of(const Eigen::VectorXd& v) { return v.cwiseAbs().maxCoeff(); }


TEST(AppCheck, TwoEnginesAgreeAndEachIsTheSolveOfItsPair) {
  const Scene scene = small_plane(8);
  std::string other;  // a second minimizer
  for (const auto& m : available_minimizers())
    if (m != "ssn" && other.empty()) other = m;
  if (other.empty()) GTEST_SKIP() << "one minimizer is built";
  CheckOptions o;
  o.pairs = {{"eigen", "ssn"}, {"eigen", other}};
  int done = 0;
  o.done = [&](const PairRun&) { ++done; };
  const CheckResult r = run_check(scene, o);
  ASSERT_EQ(r.runs.size(), 2u);
  EXPECT_EQ(done, 2);
  EXPECT_EQ(r.outcome, CheckOutcome::agree);
  ASSERT_TRUE(r.runs[0].converged && r.runs[1].converged);
  // each pair's displacement is the solve of that pair through run_scene
  for (const PairRun& run : r.runs) {
    const SceneRun solo = solve_with(scene, run.pair.linear, run.pair.minimizer);
    ASSERT_TRUE(solo.converged());
    EXPECT_LE(max_abs_of(run.u - solo.plane()->solution.u) / max_abs_of(run.u), 1e-10) << run.pair.label();
    EXPECT_NEAR(run.energy, solo.plane()->solution.energy, 1e-10 * std::abs(run.energy));
  }
  // the two engines agree to the certificate's tolerance, and the matrix says so
  const double d = max_abs_of(r.runs[0].u - r.runs[1].u) / max_abs_of(r.runs[0].u);
  EXPECT_LE(d, o.agree);
  EXPECT_DOUBLE_EQ(r.comparison.diff[0][1], d);
  EXPECT_TRUE(r.comparison.unique);
  const nlohmann::json j = check_json(scene, r);
  EXPECT_EQ(j["schema"], "hemivem-check/3");
  EXPECT_EQ(j["exit_code"], 0);
  EXPECT_EQ(j["pairs"].size(), 2u);
  EXPECT_EQ(j["verdict"], r.verdict);
}

TEST(AppCheck, AnAgreeThatIsNotPositiveIsRefusedAtItsKey) {
  CheckOptions o;
  o.agree = 0.0;
  o.agree_key = "--agree";
  EXPECT_EQ(test::input_error_key([&] { (void)run_check(small_plane(4), o); }), "--agree");
}

TEST(AppStudy, TheErrorIsTheEnergyOfTheProlongedDifferenceOfTwoSolves) {
  const Scene scene = small_plane(8);
  StudyOptions o;
  o.n = {4, 2};
  o.ref = 8;
  int solves = 0;
  o.solved = [&](const StudySolveInfo&) { ++solves; };
  const StudyResult r = run_study(scene, o);
  EXPECT_EQ(solves, 3);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[0].n, 2);  // sorted
  EXPECT_TRUE(r.references);  // Example 4.1 at any mesh size
  EXPECT_FALSE(r.rows[0].paper.has_value());  // docs/table1.md has no N = 2
  // the same numbers from two solves through app::run_scene
  const SceneRun fine = run_scene(small_plane(8));
  const SceneRun coarse = run_scene(small_plane(4));
  const Mesh& mesh = fine.plane()->built->mesh;
  const MaterialTable& materials = fine.plane()->built->problem.elasticity.materials;
  const double norm = std::sqrt(q1_energy(mesh, materials, fine.plane()->solution.u) / 2.0);
  EXPECT_NEAR(r.ref_norm, norm, 1e-12 * norm);
  const Eigen::VectorXd diff = fine.plane()->solution.u - prolong_squares(coarse.plane()->solution.u, 4, 8);
  const double error = std::sqrt(q1_energy(mesh, materials, diff) / 2.0) / norm;
  EXPECT_NEAR(r.rows[1].error, error, 1e-9 * error);
  EXPECT_NEAR(r.rows[1].h, 0.25, 1e-15);
  ASSERT_TRUE(r.rows[1].rate.has_value());
  EXPECT_NEAR(*r.rows[1].rate, std::log(r.rows[0].error / r.rows[1].error) / std::log(2.0), 1e-12);
  const nlohmann::json j = study_json(scene, o, r);
  EXPECT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["reference"]["n"], 8);
}

TEST(AppStudy, SizesThatDoNotNestAreRefusedAtTheirKey) {
  StudyOptions o;
  o.n = {3};
  o.ref = 8;
  o.n_key = "--n";
  EXPECT_EQ(test::input_error_key([&] { (void)study_sizes(small_plane(8), o); }), "--n");  // 3 does not divide 8
  o.n = {2};
  o.ref = 0;
  EXPECT_THROW((void)study_sizes(small_plane(8), o), InputError);
}

TEST(AppBench, AitkenOfAGeometricSequenceIsItsLimit) {
  // phi_k = L + C q^k: Aitken's delta-squared extrapolation is exact
  for (const double q : {0.25, 0.5, 0.9}) {
    const double limit = -0.2163, c = 0.37;
    const auto ref = aitken_reference(limit + c, limit + c * q, limit + c * q * q);
    ASSERT_TRUE(ref.has_value()) << q;
    EXPECT_NEAR(*ref, limit, 1e-14) << q;
  }
}

TEST(AppBench, ThePairOnTheReferenceMeshHasNoErrorAndACoarserOneHas) {
  const Scene scene = small_plane(4);
  BenchOptions o;
  o.n = {4, 8};
  o.ref = 8;
  o.levels = 1;
  o.pairs = {{"eigen", "ssn"}};
  int pairs_done = 0, levels_done = 0;
  o.progress.pair_done = [&](const PairRun&, int) { ++pairs_done; };
  o.progress.refinement = [&](const RefinementPoint&) { ++levels_done; };
  const BenchResult r = run_bench(scene, o);
  EXPECT_TRUE(r.plan.gridded);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(pairs_done, 2);
  EXPECT_GE(levels_done, 2);  // two uniform levels, then the adaptive steps
  EXPECT_TRUE(r.converged);
  // the reference is the scene at n = 8 solved by its pair through run_scene
  const SceneRun ref = solve_with(small_plane(8), r.reference.pair.linear, r.reference.pair.minimizer);
  EXPECT_NEAR(r.reference.scale, max_abs_of(ref.plane()->solution.u), 1e-10 * r.reference.scale);
  // the same mesh as the reference: no error but the engines' round-off; a coarser mesh: an error
  EXPECT_LT(r.rows[1].error, 1e-8);
  EXPECT_GT(r.rows[0].error, 1e-4);
  EXPECT_EQ(r.refinement.uniform.size(), 2u);
  EXPECT_FALSE(r.refinement.reference_energy.has_value());  // Aitken needs three levels
  const nlohmann::json j = bench_json(r);
  EXPECT_EQ(j["schema"], "hemivem-bench/4");
  EXPECT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["refinement"]["levels"], 1);
}

TEST(AppBench, ALevelThatIsNotPositiveIsRefusedAtItsKey) {
  BenchOptions o;
  o.levels = 0;
  o.keys.levels = "--levels";
  EXPECT_EQ(test::input_error_key([&] { check_bench_options(o); }), "--levels");
}

}  // namespace
}  // namespace hemivem::app
