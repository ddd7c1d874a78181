#include "check.hpp"

#include <hemivem/app/check.hpp>
#include <hemivem/scene/scene.hpp>

#include <nlohmann/json.hpp>

#include <iomanip>
#include <ostream>

#include "commands.hpp"
#include "common.hpp"

namespace hemivem::cli {

namespace {

/// Which pairs (by # in the table) are on the full-space route, when any is.
void print_routes(std::ostream& out, const std::vector<PairRun>& runs) {
  std::string numbers;
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (runs[i].pair.full_space()) numbers += (numbers.empty() ? "#" : ", #") + std::to_string(i + 1);
  if (numbers.empty()) return;
  out << "  full-space route (a Krylov engine with ssn's Newton iteration in the whole space, nothing factorized, "
         "no uniqueness margin): "
      << numbers << "; the others condense onto the contact unknowns\n";
}

/// The table of pairs and the matrix of their differences, as `hemivem check` prints them.
void print_check(std::ostream& out, const Scene& base, const app::CheckResult& result) {
  const std::vector<PairRun>& runs = result.runs;
  const app::CheckComparison& c = result.comparison;
  const app::CheckEnergies& e = result.energies;
  const std::size_t np = runs.size();
  out << "hemivem check: " << base.title << " (" << base.source << "), " << scene_mesh_description(base);
  out << ": " << result.vertices << " vertices"
      << (runs.empty() ? std::string() : ", " + std::to_string(runs.front().contact_nodes) + " contact nodes");
  out << "\n  tolerance " << sci(base.solver.tolerance) << ", agree " << sci(result.agree)
      << "; differences are max|u_a - u_b| / max|u_ref|, u_ref from eigen+ssn (max|u_ref| = " << sci(c.scale, 4)
      << ")\n  ";
  if (!result.path_t.empty())
    out << "a loading path of " << result.path_t.size()
        << " steps: every pair solves every step and is compared at each; a difference is the largest over the steps\n  ";
  out << c.margin_text
      << (c.unique ? ": the solution is unique, converged pairs must agree\n"
                   : ": several critical points are possible, differences between converged pairs are reported "
                     "but are not a disagreement\n");
  print_routes(out, runs);
  out << "\n" << std::left << std::setw(4) << "  #" << std::setw(12) << "linear" << std::setw(18) << "minimizer"
      << std::setw(17) << "status" << std::right << std::setw(10) << "primal" << std::setw(10) << "dual"
      << std::setw(7) << "iter" << std::setw(10) << "time [s]" << std::setw(11) << "max diff" << std::setw(18)
      << "energy" << "\n";
  for (std::size_t i = 0; i < np; ++i) {
    const auto& r = runs[i];
    out << std::right << std::setw(3) << i + 1 << " " << std::left << std::setw(12) << r.pair.linear << std::setw(18)
        << r.pair.minimizer << std::setw(17) << r.status << std::right;
    if (r.refused) {  // nothing was solved: the reason is below the verdict
      out << std::setw(10) << "-" << std::setw(10) << "-" << std::setw(7) << "-" << std::setw(10) << "-" << std::setw(11)
          << "-" << std::setw(18) << "-" << "\n";
      continue;
    }
    out << std::setw(10) << sci(r.certificate.primal) << std::setw(10) << sci(r.certificate.dual) << std::setw(7)
        << r.iterations << std::setw(10) << fixed(r.seconds) << std::setw(11) << sci(c.pair_max[i]) << std::setw(18)
        << std::setprecision(10) << r.energy
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
  if (!result.path_t.empty()) out << "\n  largest difference between converged pairs at each step\n";
  for (std::size_t k = 0; k < result.path_t.size(); ++k)
    out << "    step " << std::setw(3) << k + 1 << "  t = " << std::left << std::setw(10) << std::setprecision(6)
        << result.path_t[k] << std::right << sci(c.step_max[k]) << "\n";
  out << "\n  verdict   " << result.verdict << "\n";
  for (const auto& r : runs)
    if (r.failed) out << (r.refused ? "  refused   " : "  failed    ") << r.pair.label() << ": " << r.message << "\n";
}

}  // namespace

int run_check(const CheckOptions& o, std::ostream& out, std::ostream& err) {
  const Scene base = load_pairs_scene(o.scene, o.n, o.tolerance, o.set);
  app::CheckOptions co;
  co.agree = o.agree;
  co.agree_key = "--agree";
  if (o.verbosity >= 1)
    co.done = [&](const PairRun& r) {
      err << "hemivem check: " << std::left << std::setw(28) << r.pair.label() << r.status << " (" << fixed(r.seconds, 3)
          << " s)\n";
    };
  const app::CheckResult result = app::run_check(base, co);
  if (o.json)
    out << app::check_json(base, result).dump(2) << "\n";
  else if (o.verbosity >= 1)
    print_check(out, base, result);
  return static_cast<int>(result.outcome);
}

}  // namespace hemivem::cli
