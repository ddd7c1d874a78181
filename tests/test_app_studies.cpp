// The check, the study and the bench of hemivem::app (app/check.hpp, app/study.hpp,
// app/bench.hpp) on tiny problems, each against something computed another way: the same
// solve through app::run_scene, the study's error recomputed from two solves, Aitken's
// extrapolation of a geometric sequence, and a mesh compared with itself.
#include <gtest/gtest.h>

#include <sstream>
#include <fstream>
#include <filesystem>

#include <stdlib.h>

#include <hemivem/app/bench.hpp>
#include <hemivem/app/check.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/app/study.hpp>
#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/vem/bilinear.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

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

/// scenes/friction-coulomb.toml (Coulomb friction along a path: pressed, then sheared) on n x n
/// squares, its path cut to t = 0.5, 1, 1.5, every step a frame (its displacement kept).
Scene coulomb_path(int n) {
  Scene s = parse_scene(test::scenes_dir() / "friction-coulomb.toml");
  apply_overrides(s, {"mesh.n=" + std::to_string(n), "path.t=[0.5, 1.0, 1.5]", "path.frames=3"});
  return s;
}

/// The linear engines to pair with ssn: eigen and one more when another was built.
std::vector<Pair> two_ssn_pairs() {
  std::vector<Pair> pairs{{"eigen", "ssn"}};
  for (const auto& l : available_factorizations())
    if (l != "eigen" && l != "mumps-mpi" && pairs.size() < 2) pairs.push_back({l, "ssn"});
  return pairs;
}


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
  EXPECT_EQ(j["schema"], "hemivem-check/5");
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

TEST(AppCheck, ACoulombPathIsComparedAtEveryStepAndEachPairIsItsOwnPathSolve) {
  const Scene scene = coulomb_path(6);
  CheckOptions o;
  o.pairs = two_ssn_pairs();
  const CheckResult r = run_check(scene, o);
  ASSERT_EQ(r.runs.size(), o.pairs.size());
  EXPECT_EQ(r.path_t, (std::vector<double>{0.5, 1.0, 1.5}));
  EXPECT_EQ(r.outcome, CheckOutcome::agree) << r.verdict;
  for (const PairRun& run : r.runs) {
    ASSERT_TRUE(run.converged) << run.pair.label() << ": " << run.message;
    ASSERT_EQ(run.path_u.size(), 3u);
    // every step is the step of the same path solved through run_scene with the pair's engines
    const SceneRun solo = solve_with(scene, run.pair.linear, run.pair.minimizer);
    ASSERT_TRUE(solo.converged());
    ASSERT_TRUE(solo.plane()->path);
    const auto& steps = solo.plane()->path->steps;
    ASSERT_EQ(steps.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_LE(max_abs_of(run.path_u[k] - steps[k].u), 1e-10 * max_abs_of(steps[k].u)) << run.pair.label() << " " << k;
    EXPECT_NEAR(run.energy, solo.plane()->solution.energy, 1e-10 * std::abs(run.energy));
    EXPECT_GT(run.stick, -1);  // friction states are reported
  }
  // the difference of two pairs is the largest over the steps, each step's by hand
  if (r.runs.size() == 2) {
    double largest = 0.0, scale = 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      largest = std::max(largest, max_abs_of(r.runs[0].path_u[k] - r.runs[1].path_u[k]));
      scale = std::max(scale, max_abs_of(r.runs[0].path_u[k]));
    }
    EXPECT_DOUBLE_EQ(r.comparison.scale, scale);
    EXPECT_DOUBLE_EQ(r.comparison.diff[0][1], largest / scale);
    ASSERT_EQ(r.comparison.step_max.size(), 3u);
    EXPECT_DOUBLE_EQ(r.comparison.step_max[2], max_abs_of(r.runs[0].path_u[2] - r.runs[1].path_u[2]) / scale);
  }
  const nlohmann::json j = check_json(scene, r);
  ASSERT_TRUE(j["path"].is_object()) << j.dump(2);
  EXPECT_EQ(j["path"]["steps"].size(), 3u);
  EXPECT_EQ(j["path"]["steps"][1]["t"], 1.0);
}

// A path given its output folder writes each step's files into the folder's transaction as it
// solves it and keeps only its last step; the files are those of the path that kept every step
// (path.json but for its times, the contact rows, the frames and their collection, to the byte),
// and nothing is in the folder before the run is written.
TEST(AppPath, APathWritingAsItRunsKeepsOneStepAndWritesTheFilesOfAPathThatKeptThemAll) {
  Scene scene = coulomb_path(6);
  apply_overrides(scene, {"output.write=[\"result-json\", \"vtu\", \"displacement-csv\"]"});
  const std::filesystem::path base =
      std::filesystem::temp_directory_path() / ("hemivem-streamed-path-" + std::to_string(::getpid()));
  std::filesystem::remove_all(base);
  const SceneRun kept = run_scene(scene);
  (void)kept.write(base / "kept");
  RunOptions o;
  o.out = base / "streamed";
  const SceneRun streamed = run_scene(scene, o);
  EXPECT_FALSE(std::filesystem::exists(base / "streamed" / "path.json"));  // nothing before the commit
  ASSERT_NE(streamed.path(), nullptr);
  EXPECT_EQ(streamed.path()->steps.size(), 1u);
  EXPECT_EQ(streamed.path()->solved_steps, 3);
  EXPECT_EQ(streamed.path()->converged_steps, kept.path()->converged_steps);
  EXPECT_EQ(kept.path()->steps.size(), 3u);
  // another folder, or a chosen list of files, cannot be written: the steps are gone
  EXPECT_FALSE(test::input_error_of([&] { (void)streamed.write(base / "elsewhere"); }).empty());
  const OutputReport report = streamed.write(base / "streamed");
  auto text = [](const std::filesystem::path& file) {
    std::ostringstream out;
    out << std::ifstream(file).rdbuf();
    return out.str();
  };
  auto without_times = [](nlohmann::json j) {
    j.erase("timings");
    for (auto& step : j["steps"]) step.erase("seconds");
    return j;
  };
  const nlohmann::json a = nlohmann::json::parse(text(base / "kept" / "path.json"));
  const nlohmann::json b = nlohmann::json::parse(text(base / "streamed" / "path.json"));
  ASSERT_EQ(b["steps"].size(), 3u);
  EXPECT_EQ(without_times(a), without_times(b));
  EXPECT_TRUE(b["steps"][0]["fixed_point"].is_object());
  for (const char* name : {"path-contact.csv", "path-displacement.csv", "solution.pvd", "solution-0001.vtu",
                           "solution-0002.vtu", "solution-0003.vtu"}) {
    ASSERT_TRUE(std::filesystem::exists(base / "streamed" / name)) << name;
    EXPECT_EQ(text(base / "kept" / name), text(base / "streamed" / name)) << name;
  }
  EXPECT_EQ(text(base / "kept" / "path-contact.csv").substr(0, 5), "step,");
  EXPECT_FALSE(report.written.empty());
  // written once
  EXPECT_FALSE(test::input_error_of([&] { (void)streamed.write(base / "streamed"); }).empty());
  std::filesystem::remove_all(base);
}

// A path keeps every step's contact nodes until its files are written: a million steps do not
// fit in 1 GiB, and are refused where [path] is before anything is solved, with the memory's source.
TEST(AppPath, APathThatWouldNotFitIsRefusedBeforeItsFirstStep) {
  Scene scene = small_plane(16);
  apply_overrides(scene, {"path.steps=1000000"});
  ::setenv("HEMIVEM_MEMORY_LIMIT", "1G", 1);
  const std::string message = test::input_error_of([&] { (void)run_scene(scene); });
  const std::string key = test::input_error_key([&] { (void)run_scene(scene); });
  ::unsetenv("HEMIVEM_MEMORY_LIMIT");
  EXPECT_EQ(key, scene.where("path"));
  EXPECT_NE(message.find("a path of 1000000 steps"), std::string::npos) << message;
  EXPECT_NE(message.find("HEMIVEM_MEMORY_LIMIT"), std::string::npos) << message;
  // the same path with 100 steps fits
  apply_overrides(scene, {"path.steps=100"});
  ::setenv("HEMIVEM_MEMORY_LIMIT", "1G", 1);
  const SceneRun run = run_scene(scene);
  ::unsetenv("HEMIVEM_MEMORY_LIMIT");
  EXPECT_TRUE(run.converged());
}

TEST(AppCheck, CoulombFrictionWithoutAPathIsTheOneStepPath) {
  Scene scene = coulomb_path(4);
  scene.path.reset();  // Coulomb friction alone: the one-step path t = 1
  CheckOptions o;
  o.pairs = {{"eigen", "ssn"}};
  const CheckResult r = run_check(scene, o);
  ASSERT_EQ(r.runs.size(), 1u);
  ASSERT_TRUE(r.runs[0].converged) << r.runs[0].message;
  EXPECT_EQ(r.path_t, std::vector<double>{1.0});
  const SceneRun solo = solve_with(scene, "eigen", "ssn");
  EXPECT_LE(max_abs_of(r.runs[0].u - solo.plane()->solution.u), 1e-10 * max_abs_of(r.runs[0].u));
}

TEST(AppCheck, ASolidPathIsComparedAtEveryStep) {
  Scene scene = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  apply_overrides(scene, {"mesh.n=[2, 1, 2]", "path.t=[0.5, 1.0]", "path.frames=2"});
  CheckOptions o;
  o.pairs = two_ssn_pairs();
  const CheckResult r = run_check(scene, o);
  EXPECT_EQ(r.outcome, CheckOutcome::agree) << r.verdict;
  EXPECT_EQ(r.path_t, (std::vector<double>{0.5, 1.0}));
  for (const PairRun& run : r.runs) {
    ASSERT_EQ(run.path_u.size(), 2u) << run.pair.label();
    const SceneRun solo = solve_with(scene, run.pair.linear, run.pair.minimizer);
    ASSERT_TRUE(solo.solid() && solo.solid()->path);
    for (std::size_t k = 0; k < 2; ++k) {
      const Eigen::VectorXd& u = solo.solid()->path->steps[k].u;
      EXPECT_LE(max_abs_of(run.path_u[k] - u), 1e-10 * max_abs_of(u)) << run.pair.label() << " " << k;
    }
  }
}

/// eigen+ssn and the full-space route's pair of every Krylov engine built (eigen-cg always).
std::vector<Pair> condensed_and_full_space_pairs() {
  std::vector<Pair> pairs{{"eigen", "ssn"}};
  for (const auto& k : available_krylov_solvers()) pairs.push_back({k, "ssn"});
  return pairs;
}

// The full-space route's pairs in a check: each is the solve of its engine through run_scene
// (BasicContactSolver with the Krylov engine: its own assembly and posing), and agrees with
// the condensed pair by the same differences, on a problem whose margin (the condensed
// pair's: the route measures none) says the solution is unique.
TEST(AppCheck, FullSpacePairsAgreeWithTheCondensedPairAndAreTheSolveOfTheirEngine) {
  const Scene scene = small_plane(8);
  CheckOptions o;
  o.pairs = condensed_and_full_space_pairs();
  const CheckResult r = run_check(scene, o);
  ASSERT_EQ(r.runs.size(), o.pairs.size());
  EXPECT_EQ(r.outcome, CheckOutcome::agree) << r.verdict;
  EXPECT_TRUE(r.comparison.unique);
  EXPECT_EQ(r.comparison.refused, 0);
  EXPECT_DOUBLE_EQ(r.comparison.margin, r.runs[0].margin);
  for (std::size_t i = 1; i < r.runs.size(); ++i) {
    const PairRun& run = r.runs[i];
    SCOPED_TRACE(run.pair.label());
    ASSERT_TRUE(run.converged) << run.message;
    EXPECT_TRUE(run.pair.full_space());
    EXPECT_TRUE(std::isnan(run.margin));
    EXPECT_GT(run.timings.at("posing"), 0.0);
    EXPECT_GT(run.timings.at("full_space"), 0.0);
    EXPECT_EQ(run.timings.count("condensation"), 0u);
    EXPECT_LE(r.comparison.diff[0][i], o.agree);
    EXPECT_DOUBLE_EQ(r.comparison.diff[0][i], max_abs_of(run.u - r.runs[0].u) / max_abs_of(r.runs[0].u));
    EXPECT_NEAR(run.energy, r.runs[0].energy, 1e-9 * std::abs(run.energy));
    if (run.pair.linear != "eigen-cg") continue;  // the command's engine, alone: as the pair
    const SceneRun solo = solve_with(scene, run.pair.linear, run.pair.minimizer);
    ASSERT_TRUE(solo.converged());
    EXPECT_LE(max_abs_of(run.u - solo.plane()->solution.u), 1e-10 * max_abs_of(run.u));
  }
  const nlohmann::json j = check_json(scene, r);
  for (std::size_t i = 0; i < r.runs.size(); ++i)
    EXPECT_EQ(j["pairs"][i]["route"], i == 0 ? "condensed" : "full_space") << i;
  EXPECT_TRUE(j["refused"].empty());
}

// A solid: the cube scene's full-space pairs agree with the condensed pair.
TEST(AppCheck, FullSpacePairsAgreeOnASolid) {
  Scene scene = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  apply_overrides(scene, {"mesh.n=[4, 2, 4]"});
  CheckOptions o;
  o.pairs = condensed_and_full_space_pairs();
  const CheckResult r = run_check(scene, o);
  EXPECT_EQ(r.outcome, CheckOutcome::agree) << r.verdict;
  EXPECT_TRUE(r.comparison.unique);
  for (std::size_t i = 1; i < r.runs.size(); ++i) {
    ASSERT_TRUE(r.runs[i].converged) << r.runs[i].pair.label() << ": " << r.runs[i].message;
    EXPECT_GT(r.runs[i].u.size(), 0);
    EXPECT_LE(r.comparison.diff[0][i], o.agree) << r.runs[i].pair.label();
  }
}

// A loading path: a full-space pair solves it as solve_path on its Krylov engine does (the
// command's path through run_scene), and is compared with the condensed pair at every step.
TEST(AppCheck, AFullSpacePairSolvesThePathAndIsComparedAtEveryStep) {
  const Scene scene = coulomb_path(6);
  CheckOptions o;
  o.pairs = {{"eigen", "ssn"}, {"eigen-cg", "ssn"}};
  const CheckResult r = run_check(scene, o);
  EXPECT_EQ(r.outcome, CheckOutcome::agree) << r.verdict;
  ASSERT_EQ(r.comparison.step_max.size(), 3u);
  const PairRun& run = r.runs[1];
  ASSERT_TRUE(run.converged) << run.message;
  ASSERT_EQ(run.path_u.size(), 3u);
  EXPECT_GT(run.timings.at("posing"), 0.0);
  EXPECT_GT(run.timings.at("full_space"), 0.0);  // every step's Newton iteration
  EXPECT_EQ(run.timings.count("minimize"), 0u);
  const SceneRun solo = solve_with(scene, "eigen-cg", "ssn");
  ASSERT_TRUE(solo.converged() && solo.plane()->path);
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::VectorXd& u = solo.plane()->path->steps[k].u;
    EXPECT_LE(max_abs_of(run.path_u[k] - u), 1e-10 * max_abs_of(u)) << k;
    EXPECT_LE(r.comparison.step_max[k], o.agree) << k;
  }
}

// A block held vertically by its contact alone: the full-space pairs solve it too (in one process)
// and are compared with the condensed pair; none is refused. A full-space pair alone is a check
// of its own.
TEST(AppCheck, ABodyHeldByItsContactAloneIsCheckedOnBothRoutes) {
  Scene scene = parse_scene(test::scenes_dir() / "block-between-rollers.toml");
  apply_overrides(scene, {"mesh.n=[8, 2]"});
  CheckOptions o;
  o.pairs = condensed_and_full_space_pairs();
  const CheckResult r = run_check(scene, o);
  EXPECT_EQ(r.outcome, CheckOutcome::agree) << r.verdict;
  EXPECT_EQ(r.comparison.refused, 0);
  EXPECT_FALSE(r.comparison.any_failed);
  ASSERT_GT(r.runs.size(), 1u);
  for (std::size_t i = 0; i < r.runs.size(); ++i) {
    const PairRun& run = r.runs[i];
    SCOPED_TRACE(run.pair.label());
    EXPECT_TRUE(run.converged && !run.refused) << run.message;
    EXPECT_LE(r.comparison.diff[0][i], o.agree);
  }
  const nlohmann::json j = check_json(scene, r);
  EXPECT_EQ(j["exit_code"], 0);
  EXPECT_TRUE(j["refused"].empty());

  o.pairs = {{"eigen-cg", "ssn"}};
  const CheckResult alone = run_check(scene, o);
  ASSERT_EQ(alone.runs.size(), 1u);
  EXPECT_TRUE(alone.runs[0].converged) << alone.runs[0].message;
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
  EXPECT_EQ(j["schema"], "hemivem-bench/6");
  EXPECT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["refinement"]["levels"], 1);
}

// The full-space route's pairs in a bench: timed by their own stages and measured against the
// same reference, with the condensed pair's errors (the same discrete solution); on a scene
// the route refuses they are rows with the status "refused", and the bench still converges.
TEST(AppBench, FullSpacePairsAreTimedAndMeasuredLikeTheOthers) {
  BenchOptions o;
  o.n = {4, 8};
  o.ref = 16;
  o.levels = 1;
  o.pairs = condensed_and_full_space_pairs();
  const BenchResult r = run_bench(small_plane(4), o);
  EXPECT_TRUE(r.converged);
  ASSERT_EQ(r.rows.size(), 2 * o.pairs.size());
  const nlohmann::json j = bench_json(r);
  for (std::size_t i = 2; i < r.rows.size(); ++i) {  // rows pair by pair: eigen+ssn's are the first two
    const BenchRow& row = r.rows[i];
    SCOPED_TRACE(row.run.pair.label() + " n = " + std::to_string(row.n));
    ASSERT_TRUE(row.run.converged) << row.run.message;
    EXPECT_EQ(row.n, r.rows[i % 2].n);
    EXPECT_NEAR(row.error, r.rows[i % 2].error, 1e-6 * r.rows[i % 2].error);
    EXPECT_GT(bench_stage(row.run, "posing"), 0.0);
    EXPECT_GT(bench_stage(row.run, "full_space"), 0.0);
    EXPECT_EQ(bench_stage(row.run, "condensation"), 0.0);
    EXPECT_GE(bench_stage(row.run, "total"), bench_stage(row.run, "assembly") + bench_stage(row.run, "posing") +
                                                 bench_stage(row.run, "full_space"));
    EXPECT_EQ(j["rows"][i]["route"], "full_space");
    EXPECT_EQ(j["rows"][i]["seconds"]["full_space"].get<double>(), bench_stage(row.run, "full_space"));
  }
  EXPECT_EQ(j["rows"][0]["route"], "condensed");
  EXPECT_NE(bench_plot_script({{"eigen-cg", "ssn", {{0.1, 0.2}}}}).find("linear engine eigen-cg (full-space route)"),
            std::string::npos);

  // a body held by its contact alone, pressed uniformly: its answer is affine, which both routes
  // reproduce on every mesh (the patch test), so the error against the finer mesh is round-off
  const Scene held = parse_scene(test::scenes_dir() / "block-between-rollers.toml");
  o.n = {4};
  o.ref = 8;
  o.pairs = {{"eigen", "ssn"}, {"eigen-cg", "ssn"}};
  const BenchResult b = run_bench(held, o);
  ASSERT_EQ(b.rows.size(), 2u);
  for (const BenchRow& row : b.rows) ASSERT_TRUE(row.run.converged && !row.run.refused) << row.run.message;
  for (const BenchRow& row : b.rows) EXPECT_LE(row.error, 1e-12) << row.run.pair.label();
  EXPECT_TRUE(b.converged);
}

TEST(AppBench, APathIsBenchmarkedAtItsLastStep) {
  BenchOptions o;
  o.n = {4};
  o.ref = 8;
  o.levels = 1;
  o.pairs = {{"eigen", "ssn"}};
  const BenchResult r = run_bench(coulomb_path(4), o);
  ASSERT_EQ(r.rows.size(), 1u);
  ASSERT_TRUE(r.converged) << r.rows[0].run.message;
  // the row and the reference are the last steps of the paths run_scene solves at n = 4 and 8
  const SceneRun coarse = solve_with(coulomb_path(4), "eigen", "ssn");
  const SceneRun fine = solve_with(coulomb_path(8), r.reference.pair.linear, r.reference.pair.minimizer);
  EXPECT_LE(max_abs_of(r.rows[0].run.u - coarse.plane()->solution.u), 1e-10 * max_abs_of(r.rows[0].run.u));
  EXPECT_LE(max_abs_of(r.reference.run.u - fine.plane()->solution.u), 1e-10 * r.reference.scale);
  const Eigen::VectorXd at_fine = interpolate_squares(coarse.plane()->built->mesh, coarse.plane()->solution.u, 4,
                                                      coulomb_path(4).mesh.domain, fine.plane()->built->mesh.vertices());
  const double expected = max_abs_of(at_fine - fine.plane()->solution.u) / max_abs_of(fine.plane()->solution.u);
  EXPECT_NEAR(r.rows[0].error, expected, 1e-8 * expected);
  EXPECT_GT(r.rows[0].error, 0.0);
  // the refinement study: level 0 is the scene's path, measured at its last step; no adaptive run
  ASSERT_EQ(r.refinement.uniform.size(), 2u);
  EXPECT_NEAR(r.refinement.uniform[0].potential_energy, coarse.plane()->solution.energy,
              1e-10 * std::abs(coarse.plane()->solution.energy));
  EXPECT_EQ(r.refinement.stopped, "not_run");
  const nlohmann::json j = bench_json(r);
  ASSERT_TRUE(j["path"].is_object());
  EXPECT_EQ(j["path"]["steps"], 3);
}

TEST(AppBench, ATriangleMeshHasErrorsAgainstItsReference) {
  Scene scene = small_plane(4);
  apply_overrides(scene, {"mesh.generator=\"triangles\""});
  BenchOptions o;
  o.n = {4, 8};
  o.ref = 8;
  o.levels = 1;
  o.pairs = {{"eigen", "ssn"}};
  const BenchResult r = run_bench(scene, o);
  EXPECT_TRUE(r.plan.gridded);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_LT(r.rows[1].error, 1e-8);  // the reference's own mesh
  EXPECT_GT(r.rows[0].error, 1e-4);
  EXPECT_TRUE(bench_json(r)["rows"][0]["error"].is_number());
}

TEST(AppBench, TriangleInterpolationIsExactForALinearField) {
  const Mesh mesh = make_mesh("triangles", GridSize(3, 3), Rectangle{0.0, 1.0, 0.0, 1.0}, 0);
  Eigen::VectorXd u(2 * mesh.num_vertices());
  auto field = [](const Vec2& p) { return Vec2(0.3 + 2.0 * p.x() - p.y(), -1.0 + 0.5 * p.x() + 4.0 * p.y()); };
  for (int v = 0; v < mesh.num_vertices(); ++v) u.segment<2>(2 * v) = field(mesh.vertex(v));
  const std::vector<Vec2> points{{0.0, 0.0}, {1.0, 1.0}, {0.123, 0.877}, {0.5, 0.25}, {0.999, 0.001}, {0.4, 1.0}};
  const Eigen::VectorXd at = interpolate_triangles(mesh, u, points);
  for (std::size_t k = 0; k < points.size(); ++k)
    EXPECT_LE((at.segment<2>(2 * static_cast<Eigen::Index>(k)) - field(points[k])).norm(), 1e-13) << k;
  EXPECT_EQ(test::input_error_key([&] { (void)interpolate_triangles(mesh, u, {Vec2(1.5, 0.5)}); }), "bench");
}

TEST(AppBench, ARefSizeForAMeshWithoutErrorsIsRefusedAtItsKey) {
  Scene scene = small_plane(4);
  apply_overrides(scene, {"mesh.generator=\"voronoi\""});
  BenchOptions o;
  o.n = {4};
  o.keys.ref = "--ref";
  EXPECT_NO_THROW((void)plan_bench(scene, o));  // without --ref: no error is measured, and none is claimed
  o.ref = 8;
  EXPECT_EQ(test::input_error_key([&] { (void)plan_bench(scene, o); }), "--ref");
}

TEST(AppBench, AReferenceEnergyAboveALevelGivesThatLevelNoError) {
  BenchOptions o;
  o.n = {4};
  o.ref = 4;
  o.levels = 1;
  o.pairs = {{"eigen", "ssn"}};
  const BenchResult first = run_bench(small_plane(4), o);
  const auto& levels = first.refinement.uniform;
  ASSERT_EQ(levels.size(), 2u);
  // between the two levels: above the finer one's energy (Phi_1 < Phi_0: refinement lowers it)
  const double phi0 = levels[0].potential_energy, phi1 = levels[1].potential_energy;
  ASSERT_LT(phi1, phi0);
  o.reference_energy = 0.5 * (phi0 + phi1);
  const BenchResult r = run_bench(small_plane(4), o);
  const auto& u = r.refinement.uniform;
  EXPECT_NEAR(u[0].energy_difference, phi0 - *o.reference_energy, 1e-12 * std::abs(phi0));
  EXPECT_NEAR(u[0].error, std::sqrt(phi0 - *o.reference_energy) / u[0].norm, 1e-12);
  EXPECT_LT(u[1].energy_difference, 0.0);
  EXPECT_TRUE(std::isnan(u[1].error)) << u[1].error;  // not 0: the reference is above this level
  EXPECT_GE(r.refinement.below_reference, 1);
  EXPECT_TRUE(bench_json(r)["refinement"]["uniform"][1]["error"].is_null());
}

TEST(AppBench, LevelsThatWouldNotFitInMemoryAreRefusedBeforeAnyIsRefined) {
  // 16 levels of 4 x 4 squares: about 25 * 4^16 vertices; refused at the flag, naming the first
  // level that does not fit, once the first level is solved and before any is refined
  const Scene scene = small_plane(4);
  BenchOptions o;
  o.n = {4};
  o.ref = 8;
  o.levels = 16;
  o.keys.levels = "--levels";
  o.pairs = {{"eigen", "ssn"}};
  int levels_done = 0;
  o.progress.refinement = [&](const RefinementPoint&) { ++levels_done; };
  ::setenv("HEMIVEM_MEMORY_LIMIT", "4G", 1);
  const std::string message = test::input_error_of([&] { (void)run_bench(scene, o); });
  const std::string key = test::input_error_key([&] { (void)run_bench(scene, o); });
  ::unsetenv("HEMIVEM_MEMORY_LIMIT");
  EXPECT_EQ(key, "--levels");
  EXPECT_NE(message.find("refinement level "), std::string::npos) << message;
  EXPECT_NE(message.find("HEMIVEM_MEMORY_LIMIT"), std::string::npos) << message;
  EXPECT_EQ(levels_done, 0) << "the check comes before the first level is reported";
}

TEST(AppBench, ALevelThatIsNotPositiveIsRefusedAtItsKey) {
  BenchOptions o;
  o.levels = 0;
  o.keys.levels = "--levels";
  EXPECT_EQ(test::input_error_key([&] { check_bench_options(o); }), "--levels");
}

}  // namespace
}  // namespace hemivem::app
