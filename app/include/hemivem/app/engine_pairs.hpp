// Every (linear engine, minimizer) pair on one scene, sharing what the pairs have in common:
// the mesh and the problem are built once and assembled once; each linear engine that
// factorizes condenses that assembly once and every minimizer runs on its condensation (the
// condensed route). A Krylov engine's pair (the full-space route, docs/full-space.md: the
// engine with ssn's Newton iteration in the whole space) is BasicContactSolver with that
// engine on the same problem: it assembles and poses the problem itself (its solver takes no
// assembled system, and there is nothing to condense), and a scene the route refuses (an
// InputError) is that pair refused, not an error of the
// run. A loading path (a [path] table, or friction whose bound depends on the normal contact:
// scene_is_path) is solved by each pair along the whole path (solve_path: its own assembly
// and condensation or posing), every step's displacement kept. hemivem check, hemivem bench
// and hemivem check --extreme compare and time the pairs this runner gives them
// (app::run_check, app::run_bench).
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
  /// The linear engine is a Krylov engine (is_krylov_solver): the full-space route.
  bool full_space() const;
  /// "full_space" or "condensed", as the reports name a pair's route.
  std::string route() const { return full_space() ? "full_space" : "condensed"; }
};

/// Every built pair, linear engine major, in the order of `hemivem backends`: every engine that
/// factorizes with every minimizer (the condensed route), then every Krylov engine with ssn
/// (the full-space route, whose method is ssn's Newton iteration in the whole space: it takes
/// no other minimizer). mumps-mpi is included: the factory runs it as one process (one MPI
/// rank), which needs no launcher.
std::vector<Pair> available_pairs();

/// What one pair did.
struct PairRun {
  Pair pair;
  bool failed = false;        ///< the linear engine threw: no solution
  /// A full-space pair whose route refuses the scene (its InputError): failed
  /// too (no solution), status "refused", message the reason. Not an
  /// engine's failure: check and bench do not count it as one.
  bool refused = false;
  std::string status = "failed";
  std::string message;
  bool converged = false;
  Certificate certificate;
  int iterations = 0;
  double margin = std::numeric_limits<double>::quiet_NaN();     ///< lambda_min(S - alpha_j W) (NaN on the full-space route)
  double energy = std::numeric_limits<double>::quiet_NaN();     ///< the potential energy at the pair's solution
  double rcond = std::numeric_limits<double>::quiet_NaN();      ///< the engine's estimate (estimate_condition; NaN on the full-space route)
  double condition = std::numeric_limits<double>::quiet_NaN();  ///< kappa_1 estimate (estimate_condition; NaN on the full-space route)
  /// Seconds by stage as if the pair had run alone: the shared mesh, assembly and its linear
  /// engine's condensation, then its own minimize and back-substitution; "total" excludes mesh.
  /// A full-space pair: its own assembly, posing and full_space (with the Krylov engine's
  /// preconditioner and krylov seconds within it).
  std::map<std::string, double> timings;
  double mesh_seconds = 0.0;
  double seconds = 0.0;       ///< mesh_seconds + timings["total"]
  int contact_nodes = 0;
  int at_bound = 0;           ///< contact nodes at a bound of the constraint
  int stick = -1;             ///< contact nodes that stick (-1: no tangential unknowns)
  int unknowns = 0;
  int vertices = 0;
  /// Converged implies a finite displacement and a feasible contact point whose certificate,
  /// recomputed from the reduced problem (on the full-space route from the posed whole system,
  /// certify_full_space), holds; `broken` says what failed otherwise.
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
  bool estimate_condition = false;  ///< fill PairRun::rcond and condition (two more solves with five right-hand sides per engine)
  /// An InputError of a linear engine that factorizes (a problem it refuses) fails that engine's
  /// pairs instead of being thrown. A full-space pair's InputError is always that pair refused
  /// (PairRun::refused); when every pair is refused and this is false, the first refusal is
  /// thrown (nothing was solved: the scene cannot be checked with these pairs).
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
  double assembly_seconds = 0.0;        ///< the shared assembly (0 for a path, or without a condensed pair: each pair assembles)
  /// Times the problem was assembled: 1 shared by the condensed pairs (none without one), plus
  /// one per full-space pair that ran (its solver assembles its own); a path: one per pair.
  int assemblies = 0;
  int condensations = 0;                ///< linear engines that condensed it: one each (a path: one per condensed pair)
  int posings = 0;                      ///< full-space pairs that posed it (each its own)
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

/// The fields every report of a pair has: linear, minimizer, route ("condensed" or
/// "full_space"), status ("refused" for a full-space pair whose route refuses the scene),
/// converged, message, certificate, iterations, potential_energy.
nlohmann::json pair_json(const PairRun& run);

/// Runs `pairs` on `scene`, plane or three-dimensional, static or a loading path (its
/// solver.linear and solver.minimizer are not used; the scene's [solver.parameters] go to its
/// own minimizer only). Throws the InputError of a scene that cannot be built, and an unknown
/// engine name or a Krylov engine paired with a minimizer other than ssn before any work.
PairRuns run_pairs(const Scene& scene, const std::vector<Pair>& pairs, const PairRunOptions& options = {});

}  // namespace hemivem::app
