// Every (linear engine, minimizer) pair on one scene, sharing what the pairs have in common:
// the mesh and the problem are built once and assembled once; each linear engine condenses
// that assembly once and every minimizer runs on its condensation. A loading path (a [path]
// table, or friction whose bound depends on the normal contact: scene_is_path) is solved by
// each pair along the whole path (solve_path: its own assembly and condensation), every
// step's displacement kept. hemivem check, hemivem bench and hemivem check --extreme compare
// and time the pairs this runner gives them (app::run_check, app::run_bench).
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <hemivem/certificate.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

struct Pair {
  std::string linear, minimizer;
  std::string label() const { return linear + "+" + minimizer; }
};

/// Every built pair, linear engine major, in the order of `hemivem backends`. mumps-mpi is
/// included: the factory runs it as one process (one MPI rank), which needs no launcher.
std::vector<Pair> available_pairs();

/// What one pair did.
struct PairRun {
  Pair pair;
  bool failed = false;        ///< the linear engine threw: no solution
  std::string status = "failed";
  std::string message;
  bool converged = false;
  Certificate certificate;
  int iterations = 0;
  double margin = std::numeric_limits<double>::quiet_NaN();     ///< lambda_min(S - alpha_j W)
  double energy = std::numeric_limits<double>::quiet_NaN();     ///< the potential energy at the pair's solution
  double rcond = std::numeric_limits<double>::quiet_NaN();      ///< the engine's estimate (estimate_condition)
  double condition = std::numeric_limits<double>::quiet_NaN();  ///< kappa_1 estimate (estimate_condition)
  /// Seconds by stage as if the pair had run alone: the shared mesh, assembly and its linear
  /// engine's condensation, then its own minimize and back-substitution; "total" excludes mesh.
  std::map<std::string, double> timings;
  double mesh_seconds = 0.0;
  double seconds = 0.0;       ///< mesh_seconds + timings["total"]
  int contact_nodes = 0;
  int at_bound = 0;           ///< contact nodes at a bound of the constraint
  int stick = -1;             ///< contact nodes that stick (-1: no tangential unknowns)
  int unknowns = 0;
  int vertices = 0;
  /// Converged implies a finite displacement and a feasible contact point whose certificate,
  /// recomputed from the reduced problem, holds; `broken` says what failed otherwise.
  bool guarantee = true;
  std::string broken;
  Eigen::VectorXd u;            ///< the displacement (of a path: at its last step)
  /// A loading path: the load factor and the displacement of every step (empty for a static
  /// scene). The pair converged when every step did; status and message are then those of the
  /// first step that did not, and iterations are summed over the steps.
  std::vector<double> path_t;
  std::vector<Eigen::VectorXd> path_u;
};

struct PairRunOptions {
  bool estimate_condition = false;  ///< fill PairRun::rcond and condition (7 more solves per engine)
  /// An InputError of a linear engine (a problem it refuses) fails that engine's pairs instead
  /// of being thrown.
  bool input_errors_fail_pairs = false;
  /// Called as each pair is done (a linear engine's pairs together, when its minimizers are done).
  std::function<void(const PairRun&)> done;
};

struct PairRuns {
  std::unique_ptr<BuiltProblem> built;  ///< the mesh and problem every pair solved (a plane scene)
  std::unique_ptr<BuiltProblem3D> built3d;  ///< the same for a three-dimensional scene
  int vertices = 0;                     ///< the vertices of the mesh
  bool path = false;                    ///< the scene is a loading path (scene_is_path)
  std::vector<PairRun> runs;            ///< in the order of the pairs given
  double mesh_seconds = 0.0;            ///< build_problem
  double assembly_seconds = 0.0;        ///< the shared assembly (0 for a path: each pair assembles)
  int assemblies = 0;                   ///< times the problem was assembled: 1 (a path: one per pair)
  int condensations = 0;                ///< linear engines that condensed it: one each (a path: one per pair)
};

/// max |v_i| (0 for an empty vector).
double max_abs(const Eigen::VectorXd& v);
/// max|u| of a pair: of its displacement, and along a path the largest over the steps.
double max_abs_u(const PairRun& run);
/// The difference of two pairs, max|u_a - u_b| (unscaled): along a path the largest over the
/// steps. NaN when they do not have the same number of steps or unknowns.
double max_difference(const PairRun& a, const PairRun& b);
/// The same at step k (0-based) of a path; NaN when a pair has no such step.
double step_difference(const PairRun& a, const PairRun& b, std::size_t k);
/// The scale differences between pairs are relative to: max_abs_u of eigen+ssn when it
/// converged, else the largest max_abs_u of a converged pair, else 1 (no displacement at all).
double difference_scale(const std::vector<PairRun>& runs);
/// The uniqueness margin of a scene: the largest over the pairs that did not fail (they agree
/// to round-off); NaN when none has one.
double largest_margin(const std::vector<PairRun>& runs);

/// The fields every report of a pair has: linear, minimizer, status, converged, message,
/// certificate, iterations, potential_energy.
nlohmann::json pair_json(const PairRun& run);

/// Runs `pairs` on `scene`, plane or three-dimensional, static or a loading path (its
/// solver.linear and solver.minimizer are not used; the scene's [solver.parameters] go to its
/// own minimizer only). Throws the InputError of a scene that cannot be built, and an unknown
/// engine name before any work.
PairRuns run_pairs(const Scene& scene, const std::vector<Pair>& pairs, const PairRunOptions& options = {});

}  // namespace hemivem::app
