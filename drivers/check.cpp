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
  const std::vector<PairRun>& runs = shared.runs;
  // differences relative to max|u| of eigen+ssn (else the largest converged pair)
  const double scale = difference_scale(runs);

  const std::size_t np = runs.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::vector<double>> diff(np, std::vector<double>(np, nan));
  for (std::size_t i = 0; i < np; ++i)
    for (std::size_t j = 0; j < np; ++j)
      if (!runs[i].failed && !runs[j].failed && runs[i].u.size() == runs[j].u.size())
        diff[i][j] = max_abs(runs[i].u - runs[j].u) / scale;

  // The uniqueness margin (the largest over the pairs: they agree to round-off). Where it is
  // not positive the problem may have several critical points, and converged pairs may
  // legitimately differ: differences are reported but are not a disagreement.
  const double margin = largest_margin(runs);
  const bool unique = margin > 0.0;
  const std::string margin_text =
      "the uniqueness margin lambda_min(S - alpha_j W) = " + sci(margin) +
      (unique ? " > 0" : std::isnan(margin) ? " is unknown" : " is not positive");

  // Per pair: the largest difference to a converged pair; overall: between converged pairs.
  std::vector<double> pair_max(np, nan);
  double overall = 0.0;
  bool any_failed = false, any_unconverged = false, disagree = false;
  for (std::size_t i = 0; i < np; ++i) {
    any_failed |= runs[i].failed;
    any_unconverged |= !runs[i].failed && !runs[i].converged;
    if (runs[i].failed) continue;
    double m = 0.0;
    for (std::size_t j = 0; j < np; ++j) {
      if (!runs[j].converged || std::isnan(diff[i][j])) continue;
      m = std::max(m, diff[i][j]);
      if (runs[i].converged) {
        overall = std::max(overall, diff[i][j]);
        disagree |= unique && diff[i][j] > o.agree;
      }
    }
    pair_max[i] = m;
  }
  // Where distinct critical points are legitimate, the pairs are compared by the energy they
  // reach. Energies within 1e-9 (relative) of the lowest are the same critical point reached to
  // round-off: the first such pair in the table is named, with how many others reach it.
  double lowest_energy = nan, highest_energy = nan;
  for (const auto& r : runs)
    if (r.converged && std::isfinite(r.energy)) {
      lowest_energy = std::isnan(lowest_energy) ? r.energy : std::min(lowest_energy, r.energy);
      highest_energy = std::isnan(highest_energy) ? r.energy : std::max(highest_energy, r.energy);
    }
  const double tie = 1e-9 * std::max(1.0, std::abs(lowest_energy));
  std::size_t lowest = np;
  int at_lowest = 0, higher = 0;
  for (std::size_t i = 0; i < np; ++i) {
    if (!runs[i].converged || !std::isfinite(runs[i].energy)) continue;
    if (runs[i].energy <= lowest_energy + tie) {
      if (lowest == np) lowest = i;
      ++at_lowest;
    } else {
      ++higher;
    }
  }
  std::string energy_text;
  if (!unique && lowest < np) {
    std::ostringstream e;
    e << std::setprecision(10) << "the lowest energy, " << lowest_energy << ", is reached by "
      << runs[lowest].pair.label();
    if (at_lowest > 1) e << " and " << at_lowest - 1 << " other pair(s)";
    if (higher == 0)
      e << " (every converged pair reaches it)";
    else
      e << "; " << higher << " converged pair(s) stop higher, up to " << highest_energy;
    energy_text = e.str();
  }
  const int code = any_failed ? kBackendFailure : any_unconverged ? kNotConverged : disagree ? kDisagreement : kSuccess;

  std::ostringstream verdict;
  if (code == kSuccess && overall <= o.agree)
    verdict << "all " << np << " pairs converged and agree within " << sci(o.agree) << " (largest difference "
            << sci(overall) << ")";
  else if (code == kSuccess)
    verdict << "all " << np << " pairs converged; they differ by " << sci(overall) << " > " << sci(o.agree)
            << ", which is not a disagreement: " << margin_text << ", so distinct critical points are legitimate";
  else if (code == kBackendFailure)
    verdict << "an engine failed (exit " << code << ")";
  else if (code == kNotConverged)
    verdict << "a pair did not converge (exit " << code << ")";
  else
    verdict << "converged pairs differ by " << sci(overall) << " > " << sci(o.agree) << " (exit " << code << ")";
  if (!energy_text.empty()) verdict << "; " << energy_text;

  if (o.json) {
    nlohmann::json j;
    j["schema"] = "hemivem-check/3";
    j["version"] = HEMIVEM_VERSION;
    j["scene"] = base.title;
    j["source"] = base.source;
    j["mesh"] = base.mesh.description();
    j["tolerance"] = base.solver.tolerance;
    j["agree"] = o.agree;
    j["uniqueness_margin"] = number(margin);
    j["unique"] = unique;
    j["reference"] = {{"linear", "eigen"}, {"minimizer", "ssn"}, {"max_abs_u", scale}};
    j["pairs"] = nlohmann::json::array();
    for (std::size_t i = 0; i < np; ++i) {
      nlohmann::json p = pair_json(runs[i]);
      p["seconds"] = runs[i].seconds;
      p["max_difference"] = number(pair_max[i]);
      j["pairs"].push_back(p);
    }
    nlohmann::json m = nlohmann::json::array();
    for (const auto& row : diff) {
      nlohmann::json jr = nlohmann::json::array();
      for (double d : row) jr.push_back(number(d));
      m.push_back(jr);
    }
    j["differences"] = m;
    j["max_difference"] = overall;
    j["agree_ok"] = !disagree;
    j["lowest_energy"] = lowest == np ? nlohmann::json(nullptr)
                                      : nlohmann::json{{"linear", runs[lowest].pair.linear},
                                                       {"minimizer", runs[lowest].pair.minimizer},
                                                       {"potential_energy", number(lowest_energy)},
                                                       {"pairs_at_lowest", at_lowest},
                                                       {"pairs_higher", higher},
                                                       {"highest_converged", number(highest_energy)}};
    j["verdict"] = verdict.str();
    j["exit_code"] = code;
    out << j.dump(2) << "\n";
  } else if (o.verbosity >= 1) {
    out << "hemivem check: " << base.title << " (" << base.source << "), " << base.mesh.description();
    out << ": " << shared.built->mesh.num_vertices() << " vertices"
        << (runs.empty() ? std::string() : ", " + std::to_string(runs.front().contact_nodes) + " contact nodes");
    out << "\n  tolerance " << sci(base.solver.tolerance) << ", agree " << sci(o.agree)
        << "; differences are max|u_a - u_b| / max|u_ref|, u_ref from eigen+ssn (max|u_ref| = " << sci(scale, 4)
        << ")\n  " << margin_text
        << (unique ? ": the solution is unique, converged pairs must agree\n\n"
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
          << std::setw(11) << sci(pair_max[i]) << std::setw(18) << std::setprecision(10) << r.energy
          << (!unique && r.converged && r.energy <= lowest_energy + tie ? " (lowest)" : "") << "\n";
    }
    out << "\n  pairwise differences (rows and columns: # above)\n     ";
    for (std::size_t j = 0; j < np; ++j) out << std::setw(9) << j + 1;
    out << "\n";
    for (std::size_t i = 0; i < np; ++i) {
      out << std::setw(5) << i + 1;
      for (std::size_t j = 0; j < np; ++j) out << std::setw(9) << (i == j ? std::string("-") : sci(diff[i][j], 1));
      out << "\n";
    }
    out << "\n  verdict   " << verdict.str() << "\n";
    for (const auto& r : runs)
      if (r.failed) out << "  failed    " << r.pair.label() << ": " << r.message << "\n";
  }
  return code;
}

}  // namespace hemivem::cli
