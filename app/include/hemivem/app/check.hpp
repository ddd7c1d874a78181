// The check of a scene: every (linear, minimizer) pair of engines solves it (engine_pairs.hpp),
// on the condensed route and on the full-space route (each Krylov engine with ssn), and the
// pairs are compared with each other: the largest difference of their displacements, the
// uniqueness margin that says whether converged pairs must agree, the energies they reach and
// the verdict. A full-space pair whose route refuses the scene is reported as refused, and is
// neither a failure nor compared. `hemivem check` prints it and writes its JSON (check_json); Python's
// hemivem.check returns it. Columns, JSON fields and verdicts: docs/reference/check-bench.md.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/engine_pairs.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

struct CheckOptions {
  double agree = 1e-6;                 ///< largest relative difference of u accepted between two converged pairs
  std::string agree_key = "agree";     ///< where an `agree` that is not positive is reported (InputError)
  std::vector<Pair> pairs;             ///< the pairs compared; empty: available_pairs()
  std::function<void(const PairRun&)> done;  ///< called as each pair is done
};

/// How the pairs compare: max|u_a - u_b| / scale between every two (along a loading path the
/// largest over its steps), the largest per pair and overall, and the uniqueness margin that
/// says whether converged pairs must agree.
struct CheckComparison {
  double scale = 0.0;                          ///< max|u| of eigen+ssn (else the largest converged pair; else 1)
  std::vector<std::vector<double>> diff;       ///< NaN where a pair failed
  /// A loading path: per step, the largest difference between two converged pairs (/ scale).
  std::vector<double> step_max;
  double margin = 0.0;                         ///< the largest uniqueness margin of the pairs (NaN: unknown)
  bool unique = false;                         ///< margin > 0: converged pairs must agree
  std::string margin_text;
  std::vector<double> pair_max;                ///< per pair: the largest difference to a converged pair
  double overall = 0.0;                        ///< between converged pairs
  /// A pair that failed (a refused one does not count), one that ran and did not converge,
  /// converged pairs that differ by more than agree on a unique problem.
  bool any_failed = false, any_unconverged = false, disagree = false;
  /// Full-space pairs whose route refused the scene (PairRun::refused): reported, not a failure.
  int refused = 0;
};

/// The energies converged pairs reach: energies within `tie` (1e-9 relative) of the lowest are
/// the same critical point reached to round-off; `lowest` is the first such pair (runs.size()
/// when none converged).
struct CheckEnergies {
  double lowest_energy = std::numeric_limits<double>::quiet_NaN();
  double highest_energy = std::numeric_limits<double>::quiet_NaN();
  double tie = 0.0;
  std::size_t lowest = 0;
  int at_lowest = 0, higher = 0;
};

/// The verdict of a check; its value is the exit code of `hemivem check`, which the JSON records.
enum class CheckOutcome : int { agree = 0, not_converged = 3, engine_failed = 4, disagree = 6 };
std::string to_string(CheckOutcome outcome);

struct CheckResult {
  double agree = 1e-6;
  int vertices = 0;                    ///< the vertices of the mesh every pair solved
  /// A loading path (scene_is_path): the load factor of each step, at each of which the pairs
  /// are compared; empty for a static scene.
  std::vector<double> path_t;
  std::vector<PairRun> runs;           ///< in the order of the pairs
  CheckComparison comparison;
  CheckEnergies energies;
  std::string verdict;                 ///< the verdict in words
  CheckOutcome outcome = CheckOutcome::agree;
};

/// Solves `scene` (plane or solid, static or a loading path; its solver.tolerance for every
/// pair) with every pair and compares them. Never prints. InputError (at options.agree_key) when agree is not positive,
/// and for a scene that cannot be built or an unknown engine, before any work.
CheckResult run_check(const Scene& scene, const CheckOptions& options = {});

/// The report of `hemivem check --json` (schema hemivem-check/5) for `result` of `scene`.
nlohmann::json check_json(const Scene& scene, const CheckResult& result);

}  // namespace hemivem::app
