#include <hemivem/app/check.hpp>

#include <hemivem/error.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include <hemivem/app/format.hpp>

namespace hemivem::app {

namespace {

CheckComparison compare(const std::vector<PairRun>& runs, double agree) {
  CheckComparison c;
  // differences relative to max|u| of eigen+ssn (else the largest converged pair)
  c.scale = difference_scale(runs);
  const std::size_t np = runs.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  c.diff.assign(np, std::vector<double>(np, nan));
  for (std::size_t i = 0; i < np; ++i)
    for (std::size_t j = 0; j < np; ++j)
      if (!runs[i].failed && !runs[j].failed) c.diff[i][j] = max_difference(runs[i], runs[j]) / c.scale;
  const std::size_t steps = np ? runs.front().path_u.size() : 0;
  c.step_max.assign(steps, 0.0);
  for (std::size_t k = 0; k < steps; ++k)
    for (std::size_t i = 0; i < np; ++i)
      for (std::size_t j = i + 1; j < np; ++j)
        if (runs[i].converged && runs[j].converged)
          c.step_max[k] = std::max(c.step_max[k], step_difference(runs[i], runs[j], k) / c.scale);

  // The uniqueness margin (the largest over the pairs: they agree to round-off). Where it is
  // not positive the problem may have several critical points, and converged pairs may
  // legitimately differ: differences are reported but are not a disagreement.
  c.margin = largest_margin(runs);
  c.unique = c.margin > 0.0;
  c.margin_text = "the uniqueness margin lambda_min(S - alpha_j W) = " + sci(c.margin) +
                  (c.unique ? " > 0" : std::isnan(c.margin) ? " is unknown" : " is not positive");

  c.pair_max.assign(np, nan);
  for (std::size_t i = 0; i < np; ++i) {
    c.any_failed |= runs[i].failed && !runs[i].refused;
    c.refused += runs[i].refused;
    c.any_unconverged |= !runs[i].failed && !runs[i].converged;
    if (runs[i].failed) continue;
    double m = 0.0;
    for (std::size_t j = 0; j < np; ++j) {
      if (!runs[j].converged || std::isnan(c.diff[i][j])) continue;
      m = std::max(m, c.diff[i][j]);
      if (runs[i].converged) {
        c.overall = std::max(c.overall, c.diff[i][j]);
        c.disagree |= c.unique && c.diff[i][j] > agree;
      }
    }
    c.pair_max[i] = m;
  }
  return c;
}

CheckEnergies rank_energies(const std::vector<PairRun>& runs) {
  CheckEnergies e;
  const std::size_t np = runs.size();
  for (const auto& r : runs)
    if (r.converged && std::isfinite(r.energy)) {
      e.lowest_energy = std::isnan(e.lowest_energy) ? r.energy : std::min(e.lowest_energy, r.energy);
      e.highest_energy = std::isnan(e.highest_energy) ? r.energy : std::max(e.highest_energy, r.energy);
    }
  e.tie = 1e-9 * std::max(1.0, std::abs(e.lowest_energy));
  e.lowest = np;
  for (std::size_t i = 0; i < np; ++i) {
    if (!runs[i].converged || !std::isfinite(runs[i].energy)) continue;
    if (runs[i].energy <= e.lowest_energy + e.tie) {
      if (e.lowest == np) e.lowest = i;
      ++e.at_lowest;
    } else {
      ++e.higher;
    }
  }
  return e;
}

/// Where distinct critical points are legitimate, the pairs are compared by the energy they
/// reach: the first pair at the lowest is named, with how many others reach it.
std::string energy_text(const std::vector<PairRun>& runs, const CheckComparison& c, const CheckEnergies& e) {
  if (c.unique || e.lowest >= runs.size()) return "";
  std::ostringstream t;
  t << std::setprecision(10) << "the lowest energy, " << e.lowest_energy << ", is reached by "
    << runs[e.lowest].pair.label();
  if (e.at_lowest > 1) t << " and " << e.at_lowest - 1 << " other pair(s)";
  if (e.higher == 0)
    t << " (every converged pair reaches it)";
  else
    t << "; " << e.higher << " converged pair(s) stop higher, up to " << e.highest_energy;
  return t.str();
}

CheckOutcome outcome_of(const CheckComparison& c) {
  return c.any_failed        ? CheckOutcome::engine_failed
         : c.any_unconverged ? CheckOutcome::not_converged
         : c.disagree        ? CheckOutcome::disagree
                             : CheckOutcome::agree;
}

/// The full-space pairs whose route refused the scene, in words (empty: none).
std::string refused_text(const std::vector<PairRun>& runs) {
  std::string labels;
  for (const auto& r : runs)
    if (r.refused) labels += (labels.empty() ? "" : ", ") + r.pair.label();
  if (labels.empty()) return "";
  return labels + " refused the scene (the full-space route does not take it, which is not a failure: see the "
                  "pairs' messages)";
}

std::string verdict_text(const CheckComparison& c, std::size_t pairs, double agree, const std::string& energy,
                         const std::string& refused) {
  const CheckOutcome outcome = outcome_of(c);
  const int code = static_cast<int>(outcome);
  const std::size_t np = pairs - static_cast<std::size_t>(c.refused);  // the pairs that ran
  std::ostringstream verdict;
  if (outcome == CheckOutcome::agree && c.overall <= agree)
    verdict << "all " << np << " pairs converged and agree within " << sci(agree) << " (largest difference "
            << sci(c.overall) << ")";
  else if (outcome == CheckOutcome::agree)
    verdict << "all " << np << " pairs converged; they differ by " << sci(c.overall) << " > " << sci(agree)
            << ", which is not a disagreement: " << c.margin_text << ", so distinct critical points are legitimate";
  else if (outcome == CheckOutcome::engine_failed)
    verdict << "an engine failed (exit " << code << ")";
  else if (outcome == CheckOutcome::not_converged)
    verdict << "a pair did not converge (exit " << code << ")";
  else
    verdict << "converged pairs differ by " << sci(c.overall) << " > " << sci(agree) << " (exit " << code << ")";
  if (!energy.empty()) verdict << "; " << energy;
  if (!refused.empty()) verdict << "; " << refused;
  return verdict.str();
}

}  // namespace

std::string to_string(CheckOutcome outcome) {
  switch (outcome) {
    case CheckOutcome::agree: return "agree";
    case CheckOutcome::not_converged: return "not_converged";
    case CheckOutcome::engine_failed: return "engine_failed";
    case CheckOutcome::disagree: return "disagree";
  }
  return "unknown";
}

CheckResult run_check(const Scene& scene, const CheckOptions& o) {
  if (!(o.agree > 0.0)) throw InputError("must be > 0", o.agree_key);
  PairRunOptions ro;
  ro.done = o.done;
  PairRuns shared = run_pairs(scene, o.pairs.empty() ? available_pairs() : o.pairs, ro);
  CheckResult r;
  r.agree = o.agree;
  r.vertices = shared.vertices;
  r.runs = std::move(shared.runs);
  if (shared.path)
    for (const PairRun& run : r.runs)
      if (!run.failed) {
        r.path_t = run.path_t;
        break;
      }
  r.comparison = compare(r.runs, o.agree);
  r.energies = rank_energies(r.runs);
  r.outcome = outcome_of(r.comparison);
  r.verdict = verdict_text(r.comparison, r.runs.size(), o.agree, energy_text(r.runs, r.comparison, r.energies),
                           refused_text(r.runs));
  return r;
}

/// The report of `hemivem check --json` (schema hemivem-check/5).
nlohmann::json check_json(const Scene& base, const CheckResult& result) {
  const std::vector<PairRun>& runs = result.runs;
  const CheckComparison& c = result.comparison;
  const CheckEnergies& e = result.energies;
  const std::size_t np = runs.size();
  nlohmann::json j;
  j["schema"] = "hemivem-check/5";
  j["version"] = HEMIVEM_VERSION;
  j["scene"] = base.title;
  j["source"] = base.source;
  j["mesh"] = scene_mesh_description(base);
  j["tolerance"] = base.solver.tolerance;
  j["agree"] = result.agree;
  j["uniqueness_margin"] = number(c.margin);
  j["unique"] = c.unique;
  j["reference"] = {{"linear", "eigen"}, {"minimizer", "ssn"}, {"max_abs_u", c.scale}};
  j["pairs"] = nlohmann::json::array();
  for (std::size_t i = 0; i < np; ++i) {
    nlohmann::json p = pair_json(runs[i]);
    p["seconds"] = runs[i].seconds;
    p["max_difference"] = number(c.pair_max[i]);
    j["pairs"].push_back(p);
  }
  nlohmann::json m = nlohmann::json::array();
  for (const auto& row : c.diff) {
    nlohmann::json jr = nlohmann::json::array();
    for (double d : row) jr.push_back(number(d));
    m.push_back(jr);
  }
  j["differences"] = m;
  if (!result.path_t.empty()) {
    nlohmann::json steps = nlohmann::json::array();
    for (std::size_t k = 0; k < result.path_t.size(); ++k)
      steps.push_back({{"step", k + 1}, {"t", result.path_t[k]},
                       {"max_difference", k < c.step_max.size() ? number(c.step_max[k]) : nlohmann::json(nullptr)}});
    j["path"] = {{"compared", "every step"}, {"steps", steps}};
  } else {
    j["path"] = nullptr;
  }
  j["max_difference"] = c.overall;
  j["agree_ok"] = !c.disagree;
  j["refused"] = nlohmann::json::array();  // the full-space pairs whose route refused the scene
  for (const auto& r : runs)
    if (r.refused) j["refused"].push_back(r.pair.label());
  j["lowest_energy"] = e.lowest == np ? nlohmann::json(nullptr)
                                      : nlohmann::json{{"linear", runs[e.lowest].pair.linear},
                                                       {"minimizer", runs[e.lowest].pair.minimizer},
                                                       {"potential_energy", number(e.lowest_energy)},
                                                       {"pairs_at_lowest", e.at_lowest},
                                                       {"pairs_higher", e.higher},
                                                       {"highest_converged", number(e.highest_energy)}};
  j["verdict"] = result.verdict;
  j["exit_code"] = static_cast<int>(result.outcome);
  return j;
}

}  // namespace hemivem::app
