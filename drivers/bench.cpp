#include "bench.hpp"

#include <hemivem/scene/scene.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <ostream>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include <hemivem/app/outputs.hpp>

namespace hemivem::cli {

namespace {

// The stages of the terminal table (posing and full_space: a full-space pair's); the files
// also have linear_solve (the single solve of a scene without contact).
const std::vector<std::string>& stage_names() {
  static const std::vector<std::string> names{"mesh",              "assembly", "condensation", "minimize",
                                              "back_substitution", "posing",   "full_space",   "total"};
  return names;
}

std::string refinement_line(const RefinementPoint& p) {
  std::ostringstream o;
  o << "hemivem bench: " << p.kind << (p.kind == "uniform" ? " level " : " step ") << p.index << ": " << p.unknowns
    << " unknowns, estimate " << (std::isfinite(p.estimate) ? fixed(100.0 * p.estimate, 3) + " %" : std::string("-"))
    << ", energy " << std::setprecision(10) << p.potential_energy << ", " << p.status << " (" << fixed(p.seconds, 3)
    << " s)\n";
  return o.str();
}

std::string percent_or_dash(double v) { return std::isfinite(v) ? fixed(100.0 * v, 3) + " %" : std::string("-"); }

void print_refinement(std::ostream& out, const Refinement& r, const BenchOptions& o, const std::string& plot_failure) {
  const int levels = r.levels;
  const std::string times = std::to_string(levels) + " time" + (levels > 1 ? "s" : "");
  out << "\n  refinement study: " << r.engines
      << (r.method == "cells_doubled" ? " on the scene's mesh with its cell counts doubled " + times + " (the generator remade)"
                                      : " on the scene's mesh refined uniformly " + times)
      << (r.stopped == "not_run" ? ", adaptive not run: " + r.reason : ", and adaptively (" + r.stopped + ")") << "\n";
  out << "  reference energy: ";
  if (r.reference_energy) out << std::setprecision(10) << *r.reference_energy << " (" << r.reference << ")\n";
  else out << r.reference << "\n";
  if (r.below_reference > 0)
    out << "  warning: " << r.below_reference << " point" << (r.below_reference > 1 ? "s have" : " has")
        << " a potential energy below the reference: the reference is too high (no true error there, and too "
           "small ones elsewhere); give --reference-energy from a finer run\n";
  out << "  time: " << (r.method == "cells_doubled" ? "the level's solve" : "uniform the level's solve, adaptive since its start")
      << "; true error sqrt(Phi_h - Phi_ref) / ||u_h||_E\n\n";
  out << std::left << std::setw(10) << "kind" << std::right << std::setw(6) << "#" << std::setw(11) << "unknowns"
      << std::setw(11) << "time [s]" << std::setw(12) << "estimate" << std::setw(13) << "true error" << std::setw(13)
      << "effectivity" << "\n";
  for (const auto* list : {&r.uniform, &r.adaptive})
    for (const auto& p : *list)
      out << std::left << std::setw(10) << p.kind << std::right << std::setw(6) << p.index << std::setw(11)
          << p.unknowns << std::setw(11) << fixed(p.seconds, 3) << std::setw(12) << percent_or_dash(p.estimate)
          << std::setw(13) << percent_or_dash(p.error) << std::setw(13)
          << (std::isfinite(p.effectivity) ? fixed(p.effectivity, 2) : std::string("-")) << "\n";
  if (!r.reason.empty() && r.method != "cells_doubled") out << "  adaptive: " << r.reason << "\n";
  if (plot_failure.empty()) out << "  wrote     " << o.out << "/bench-error.png\n";
  else out << "  skipped   bench-error.png: " << plot_failure << "\n";
}


void print_bench(std::ostream& out, const BenchOptions& o, const app::BenchResult& result, const std::string& plot_failure) {
  const Scene& base = result.plan.base;
  const app::BenchReference& ref = result.reference;
  const int ref_n = *result.plan.options.ref;
  out << "hemivem bench: " << base.title << " (" << base.source << ")";
  if (result.plan.gridded)
    out << "; reference " << ref.pair.label() << " on " << base.mesh.generator << " n = " << ref_n << " ("
        << ref.run.status << ", " << fixed(ref.run.seconds, 3) << " s)";
  out << "\n  " << (base.dimension() == 3 ? "N: N x N x N cells; " : "")
      << "times in seconds; error = max|I_h u_h - u_ref| / max|u_ref| at the reference vertices\n";
  if (std::any_of(result.rows.begin(), result.rows.end(), [](const app::BenchRow& r) { return r.run.pair.full_space(); }))
    out << "  a Krylov engine's pair is on the full-space route: it assembles and poses the problem itself (posing) and "
           "runs ssn's Newton iteration in the whole space (full-space); nothing is condensed\n";
  if (const nlohmann::json path = app::bench_path_json(base); !path.is_null())
    out << "  a loading path of " << path["steps"].get<std::size_t>() << " step(s), measured at "
        << path["measured"].get<std::string>()
        << "\n";
  out << "\n";
  out << std::left << std::setw(12) << "linear" << std::setw(18) << "minimizer" << std::right << std::setw(5) << "N"
      << "  " << std::left << std::setw(16) << "status" << std::right;
  for (const char* h : {"mesh", "assembly", "condense", "minimize", "back-sub", "posing", "full-space", "total"})
    out << std::setw(11) << h;
  out << std::setw(11) << "error" << "\n";
  for (const auto& r : result.rows) {
    out << std::left << std::setw(12) << r.run.pair.linear << std::setw(18) << r.run.pair.minimizer << std::right
        << std::setw(5) << r.n << "  " << std::left << std::setw(16) << r.run.status << std::right;
    for (const auto& s : stage_names()) out << std::setw(11) << fixed(app::bench_stage(r.run, s));
    out << std::setw(11) << (std::isfinite(r.error) ? sci(r.error) : std::string("null")) << "\n";
  }
  std::set<std::string> said;  // each refused pair's reason, once
  for (const auto& r : result.rows)
    if (r.run.refused && said.insert(r.run.pair.label()).second)
      out << "  refused   " << r.run.pair.label() << ": " << r.run.message << "\n";
  out << "\n  wrote     " << o.out << "/ (bench.csv, bench.json" << (plot_failure.empty() ? ", bench.png" : "")
      << ")\n";
  if (!plot_failure.empty()) out << "  skipped   bench.png: " << plot_failure << "\n";
}

/// The bench's progress lines (stderr).
app::BenchProgress bench_progress(std::ostream& err) {
  app::BenchProgress p;
  p.reference_started = [&err](const Pair& pair, int n) {
    err << "hemivem bench: reference " << pair.label() << " at n = " << n << " ... " << std::flush;
  };
  p.reference_done = [&err](const PairRun& run) { err << run.status << " (" << fixed(run.seconds, 3) << " s)\n"; };
  p.not_gridded = [&err](const std::string& generator) {
    err << "hemivem bench: the scene's mesh is not " << generator << ": errors are not computed\n";
  };
  p.pair_done = [&err](const PairRun& r, int n) {
    err << "hemivem bench: " << std::left << std::setw(28) << r.pair.label() << "n = " << std::setw(5) << n << r.status
        << " (" << fixed(r.seconds, 3) << " s)\n";
  };
  p.refinement = [&err](const RefinementPoint& point) { err << refinement_line(point); };
  return p;
}

}  // namespace

int run_bench(const BenchOptions& given, std::ostream& out, std::ostream& err) {
  app::BenchOptions ao;
  ao.n = given.n;
  ao.ref = given.ref;
  ao.levels = given.levels;
  ao.reference_energy = given.reference_energy;
  ao.keys = {"--n", "--ref", "--levels", "--reference-energy"};
  app::check_bench_options(ao);
  const Scene base = load_pairs_scene(given.scene, std::nullopt, given.tolerance, given.set);
  app::BenchPlan plan = app::plan_bench(base, ao);
  check_output_folder(given.out);
  say_what_an_interruption_keeps(given.out);
  if (given.verbosity >= 1) plan.options.progress = bench_progress(err);
  const app::BenchResult result = app::run_bench(plan);
  const app::BenchFiles files = app::write_bench(given.out, result);
  for (const auto& w : files.warnings) err << "hemivem: warning: " << w << "\n";  // a plot not drawn
  if (given.json)
    out << files.json.dump(2) << "\n";
  else if (given.verbosity >= 1) {
    print_bench(out, given, result, files.plot_skipped);
    print_refinement(out, result.refinement, given, files.refinement_plot_skipped);
  }
  return result.converged ? kSuccess : kNotConverged;
}

}  // namespace hemivem::cli
