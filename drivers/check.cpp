#include "check.hpp"

#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <memory>
#include <ostream>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "engine_pairs.hpp"

namespace hemivem::cli {

namespace {

/// How the pairs compare: max|u_a - u_b| / scale between every two, the largest per pair and
/// overall, and the uniqueness margin that says whether converged pairs must agree.
struct Comparison {
  double scale = 0.0;
  std::vector<std::vector<double>> diff;
  double margin = 0.0;
  bool unique = false;
  std::string margin_text;
  std::vector<double> pair_max;  ///< per pair: the largest difference to a converged pair
  double overall = 0.0;          ///< between converged pairs
  bool any_failed = false, any_unconverged = false, disagree = false;
};

/// The energies converged pairs reach: energies within 1e-9 (relative) of the lowest are the
/// same critical point reached to round-off; `lowest` is the first such pair in the table
/// (runs.size() when none converged).
struct EnergyRanking {
  double lowest_energy = std::numeric_limits<double>::quiet_NaN();
  double highest_energy = std::numeric_limits<double>::quiet_NaN();
  double tie = 0.0;
  std::size_t lowest = 0;
  int at_lowest = 0, higher = 0;
};

Comparison compare(const std::vector<PairRun>& runs, double agree) {
  Comparison c;
  // differences relative to max|u| of eigen+ssn (else the largest converged pair)
  c.scale = difference_scale(runs);
  const std::size_t np = runs.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  c.diff.assign(np, std::vector<double>(np, nan));
  for (std::size_t i = 0; i < np; ++i)
    for (std::size_t j = 0; j < np; ++j)
      if (!runs[i].failed && !runs[j].failed && runs[i].u.size() == runs[j].u.size())
        c.diff[i][j] = max_abs(runs[i].u - runs[j].u) / c.scale;

  // The uniqueness margin (the largest over the pairs: they agree to round-off). Where it is
  // not positive the problem may have several critical points, and converged pairs may
  // legitimately differ: differences are reported but are not a disagreement.
  c.margin = largest_margin(runs);
  c.unique = c.margin > 0.0;
  c.margin_text = "the uniqueness margin lambda_min(S - alpha_j W) = " + sci(c.margin) +
                  (c.unique ? " > 0" : std::isnan(c.margin) ? " is unknown" : " is not positive");

  c.pair_max.assign(np, nan);
  for (std::size_t i = 0; i < np; ++i) {
    c.any_failed |= runs[i].failed;
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

EnergyRanking rank_energies(const std::vector<PairRun>& runs) {
  EnergyRanking e;
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
std::string energy_text(const std::vector<PairRun>& runs, const Comparison& c, const EnergyRanking& e) {
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

int exit_code(const Comparison& c) {
  return c.any_failed ? kBackendFailure : c.any_unconverged ? kNotConverged : c.disagree ? kDisagreement : kSuccess;
}

std::string verdict_text(const Comparison& c, std::size_t np, double agree, const std::string& energy) {
  const int code = exit_code(c);
  std::ostringstream verdict;
  if (code == kSuccess && c.overall <= agree)
    verdict << "all " << np << " pairs converged and agree within " << sci(agree) << " (largest difference "
            << sci(c.overall) << ")";
  else if (code == kSuccess)
    verdict << "all " << np << " pairs converged; they differ by " << sci(c.overall) << " > " << sci(agree)
            << ", which is not a disagreement: " << c.margin_text << ", so distinct critical points are legitimate";
  else if (code == kBackendFailure)
    verdict << "an engine failed (exit " << code << ")";
  else if (code == kNotConverged)
    verdict << "a pair did not converge (exit " << code << ")";
  else
    verdict << "converged pairs differ by " << sci(c.overall) << " > " << sci(agree) << " (exit " << code << ")";
  if (!energy.empty()) verdict << "; " << energy;
  return verdict.str();
}

/// The report of `hemivem check --json` (schema hemivem-check/3).
nlohmann::json check_json(const Scene& base, const CheckOptions& o, const std::vector<PairRun>& runs,
                          const Comparison& c, const EnergyRanking& e, const std::string& verdict) {
  const std::size_t np = runs.size();
  nlohmann::json j;
  j["schema"] = "hemivem-check/3";
  j["version"] = HEMIVEM_VERSION;
  j["scene"] = base.title;
  j["source"] = base.source;
  j["mesh"] = base.mesh.description();
  j["tolerance"] = base.solver.tolerance;
  j["agree"] = o.agree;
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
  j["max_difference"] = c.overall;
  j["agree_ok"] = !c.disagree;
  j["lowest_energy"] = e.lowest == np ? nlohmann::json(nullptr)
                                      : nlohmann::json{{"linear", runs[e.lowest].pair.linear},
                                                       {"minimizer", runs[e.lowest].pair.minimizer},
                                                       {"potential_energy", number(e.lowest_energy)},
                                                       {"pairs_at_lowest", e.at_lowest},
                                                       {"pairs_higher", e.higher},
                                                       {"highest_converged", number(e.highest_energy)}};
  j["verdict"] = verdict;
  j["exit_code"] = exit_code(c);
  return j;
}

/// The table of pairs and the matrix of their differences, as `hemivem check` prints them.
void print_check(std::ostream& out, const Scene& base, const CheckOptions& o, const PairRuns& shared,
                 const Comparison& c, const EnergyRanking& e, const std::string& verdict) {
  const std::vector<PairRun>& runs = shared.runs;
  const std::size_t np = runs.size();
  out << "hemivem check: " << base.title << " (" << base.source << "), " << base.mesh.description();
  out << ": " << shared.vertices << " vertices"
      << (runs.empty() ? std::string() : ", " + std::to_string(runs.front().contact_nodes) + " contact nodes");
  out << "\n  tolerance " << sci(base.solver.tolerance) << ", agree " << sci(o.agree)
      << "; differences are max|u_a - u_b| / max|u_ref|, u_ref from eigen+ssn (max|u_ref| = " << sci(c.scale, 4)
      << ")\n  " << c.margin_text
      << (c.unique ? ": the solution is unique, converged pairs must agree\n\n"
                   : ": several critical points are possible, differences between converged pairs are reported "
                     "but are not a disagreement\n\n");
  out << std::left << std::setw(4) << "  #" << std::setw(10) << "linear" << std::setw(18) << "minimizer"
      << std::setw(17) << "status" << std::right << std::setw(10) << "primal" << std::setw(10) << "dual"
      << std::setw(7) << "iter" << std::setw(10) << "time [s]" << std::setw(11) << "max diff" << std::setw(18)
      << "energy" << "\n";
  for (std::size_t i = 0; i < np; ++i) {
    const auto& r = runs[i];
    out << std::right << std::setw(3) << i + 1 << " " << std::left << std::setw(10) << r.pair.linear << std::setw(18)
        << r.pair.minimizer << std::setw(17) << r.status << std::right << std::setw(10) << sci(r.certificate.primal)
        << std::setw(10) << sci(r.certificate.dual) << std::setw(7) << r.iterations << std::setw(10) << fixed(r.seconds)
        << std::setw(11) << sci(c.pair_max[i]) << std::setw(18) << std::setprecision(10) << r.energy
        << (!c.unique && r.converged && r.energy <= e.lowest_energy + e.tie ? " (lowest)" : "") << "\n";
  }
  out << "\n  pairwise differences (rows and columns: # above)\n     ";
  for (std::size_t j = 0; j < np; ++j) out << std::setw(9) << j + 1;
  out << "\n";
  for (std::size_t i = 0; i < np; ++i) {
    out << std::setw(5) << i + 1;
    for (std::size_t j = 0; j < np; ++j) out << std::setw(9) << (i == j ? std::string("-") : sci(c.diff[i][j], 1));
    out << "\n";
  }
  out << "\n  verdict   " << verdict << "\n";
  for (const auto& r : runs)
    if (r.failed) out << "  failed    " << r.pair.label() << ": " << r.message << "\n";
}

}  // namespace

int run_check(const CheckOptions& o, std::ostream& out, std::ostream& err) {
  if (!(o.agree > 0.0)) throw InputError("must be > 0", "--agree");
  const Scene base = load_pairs_scene(o.scene, o.n, o.tolerance, o.set);
  const bool progress = o.verbosity >= 1;
  PairRunOptions ro;
  if (progress)
    ro.done = [&](const PairRun& r) {
      err << "hemivem check: " << std::left << std::setw(28) << r.pair.label() << r.status << " (" << fixed(r.seconds, 3)
          << " s)\n";
    };
  const PairRuns shared = run_pairs(base, available_pairs(), ro);
  const Comparison c = compare(shared.runs, o.agree);
  const EnergyRanking e = rank_energies(shared.runs);
  const std::string verdict = verdict_text(c, shared.runs.size(), o.agree, energy_text(shared.runs, c, e));
  if (o.json)
    out << check_json(base, o, shared.runs, c, e, verdict).dump(2) << "\n";
  else if (o.verbosity >= 1)
    print_check(out, base, o, shared, c, e, verdict);
  return exit_code(c);
}

}  // namespace hemivem::cli
