// hemivem bench --limit: every stage of a solve against the machine's limit, measured by
// hemivem::app::run_limit (hemivem/app/limit.hpp); here the table, the ratios and limit.json
// (drivers/limit.hpp).
#include "limit.hpp"

#include "commands.hpp"
#include "common.hpp"
#include <hemivem/app/limit.hpp>
#include <hemivem/support/output_folder.hpp>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace hemivem::cli {

namespace fs = std::filesystem;

namespace {

/// The seconds of each stage per size, against the limit.
void print_limit_table(std::ostream& out, const Scene& base, const BenchOptions& o, const std::vector<app::LimitRow>& table) {
  out << "hemivem bench --limit: " << base.title << ", cholmod + " << base.solver.minimizer
      << "; limit = plain Q1 assembly + one CHOLMOD analysis and factorization of the same A"
      << (o.repeat > 1 ? "; the fastest of " + std::to_string(o.repeat) + " measurements of each" : std::string()) << "\n\n";
  out << std::left << std::setw(6) << "n" << std::right << std::setw(9) << "dofs" << std::setw(8) << "mesh"
      << std::setw(8) << "setup" << std::setw(10) << "assembly" << std::setw(8) << "condens" << std::setw(8) << "cond"
      << std::setw(8) << "minim" << std::setw(8) << "back" << std::setw(8) << "post" << std::setw(8) << "release" << std::setw(8) << "estim"
      << std::setw(8) << "result" << std::setw(8) << "other" << std::setw(8) << "solve"
      << std::setw(8) << "margin" << std::setw(9)
      << "outputs" << std::setw(9)
      << "plain" << std::setw(10) << "factor" << std::setw(9) << "peakMB" << "\n";
  for (const auto& r : table) {
    out << std::left << std::setw(6) << r.n << std::right << std::setw(9) << r.dofs;
    double staged = 0.0;
    for (const char* k : {"mesh", "setup", "assembly", "condensation", "condition", "minimize", "back_substitution",
                          "post_process", "release", "estimate", "result_json"}) {
      out << std::setw(std::string(k) == "assembly" ? 10 : 8) << fixed(r.stage.at(k), 2);
      staged += r.stage.at(k);
    }
    out << std::setw(8) << fixed(r.solve - staged, 2) << std::setw(8) << fixed(r.solve, 2) << std::setw(8) << fixed(r.stage.at("margin"), 2) << std::setw(9)
        << fixed(r.stage.at("outputs"), 2) << std::setw(9) << fixed(r.plain_assembly, 2) << std::setw(10)
        << (fixed(r.analysis + r.factorization, 2) + (r.ordering == "amd" ? "a" : "m")) << std::setw(9)
        << fixed(r.peak_rss / 1048576.0, 0) << "\n";
  }
}

/// Each ratio per size, with its target.
void print_ratios(std::ostream& out, const std::vector<app::LimitRow>& table) {
  out << "\nratios (target)        ";
  for (const auto& r : table) out << std::setw(9) << ("n=" + std::to_string(r.n));
  out << "\n";
  const std::size_t count = app::limit_ratios(table.front()).size();
  for (std::size_t q = 0; q < count; ++q) {
    const app::LimitRatio first = app::limit_ratios(table.front())[q];
    std::ostringstream target;
    target << first.target;
    out << std::left << std::setw(23) << (first.label + " (" + target.str() + ")") << std::right;
    for (const auto& r : table) {
      const double v = app::limit_ratios(r)[q].value;
      out << std::setw(9) << (std::isfinite(v) ? fixed(v, 2) : "-");
    }
    out << "\n";
  }
}

}  // namespace

int run_bench_limit(const BenchOptions& o, const std::vector<int>& sizes, std::ostream& out, std::ostream& err) {
  app::LimitOptions lo;
  lo.sizes = sizes;
  lo.repeat = o.repeat;
  lo.keys = {"--n", "--repeat", "--limit"};
  app::check_limit_options(lo);
  SolveOptions so;
  so.scene = o.scene;
  so.tolerance = o.tolerance;
  so.set = o.set;
  const Scene scene = load_scene(so);
  if (o.verbosity >= 1) {
    lo.size_started = [&err](int n) { err << "hemivem bench --limit: n = " << n << " ... " << std::flush; };
    lo.size_done = [&err](const app::LimitRow&) { err << "done\n"; };
  }
  const app::LimitResult result = app::run_limit(scene, lo);
  const nlohmann::json doc = app::limit_json(result);
  OutputTransaction tx(o.out, {"limit.json"});  // the folder changes at once
  tx.write("limit.json", [&](std::ostream& os) { os << doc.dump(2) << "\n"; });
  (void)tx.commit();
  if (o.json) {
    out << doc.dump(2) << "\n";
    return kSuccess;
  }
  if (o.verbosity < 1) return kSuccess;
  print_limit_table(out, result.plan.base, o, result.rows);
  print_ratios(out, result.rows);
  out << "\nseconds; solve: the wall time from the scene to result.json (its stages before it; release: the\n"
         "solver and its factor given back; other: the rest of it); margin (inside the condensation) and outputs\n"
         "(all files) timed again after it; factor: analysis + factorization with CHOLMOD's faster ordering\n"
         "(a: AMD, m: METIS); peak: the peak RSS of the solve's process; wrote "
      << (fs::path(o.out) / "limit.json").string() << "\n";
  return kSuccess;
}

}  // namespace hemivem::cli
