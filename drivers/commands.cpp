#include "commands.hpp"

#include <hemivem/krylov_solver.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/process_group.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/uniqueness.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <iomanip>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>

#include "common.hpp"

#include <hemivem/app/report.hpp>

namespace hemivem::cli {

Scene load_scene(const SolveOptions& o) {
  Scene scene = o.scene.empty() ? default_scene() : parse_scene(o.scene);
  // every flag and --set at once: validated together, in no particular order
  std::vector<std::string> overrides;
  if (o.mesh) {
    const std::string ext = std::filesystem::path(*o.mesh).extension().string();
    const bool file = o.mesh->find('/') != std::string::npos || !ext.empty();
    std::vector<std::string> kinds = mesh_generator_names();  // the generators of either dimension
    for (const auto& k : mesh3d_generator_names())
      if (std::find(kinds.begin(), kinds.end(), k) == kinds.end()) kinds.push_back(k);
    std::string list;
    for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
    if (file && ext != ".poly2d" && ext != ".msh")
      throw InputError("'" + *o.mesh + "' is neither a mesh generator (" + list + ") nor a .poly2d or .msh file", "--mesh");
    if (!file && std::find(kinds.begin(), kinds.end(), *o.mesh) == kinds.end())
      throw InputError("unknown mesh generator '" + *o.mesh + "'" + did_you_mean(*o.mesh, kinds) + " (expected one of: " +
                           list + ", or a .poly2d or .msh file)",
                       "--mesh");
    overrides.push_back((file ? "mesh.file=" : "mesh.generator=") + toml_string(*o.mesh));
  }
  if (o.n) overrides.push_back("mesh.n=" + std::to_string(*o.n));
  if (o.linear) overrides.push_back("solver.linear=" + toml_string(*o.linear));
  if (o.minimizer) overrides.push_back("solver.minimizer=" + toml_string(*o.minimizer));
  if (o.global) overrides.push_back("solver.search=\"global\"");
  if (o.tolerance) {
    std::ostringstream v;
    v << std::setprecision(17) << *o.tolerance;
    overrides.push_back("solver.tolerance=" + v.str());
  }
  if (o.figures) overrides.push_back(figure_format_override(*o.figures));
  // the flag behind each key a flag sets, for messages
  std::vector<std::pair<std::string, std::string>> flags;
  for (const auto& kv : overrides) {
    const std::string key = kv.substr(0, kv.find('='));
    flags.emplace_back("--set " + key, key == "mesh.file" || key == "mesh.generator" ? "--mesh"
                                       : key == "mesh.n"                            ? "--n"
                                       : key == "solver.linear"                     ? "--linear"
                                       : key == "solver.minimizer"                  ? "--minimizer"
                                       : key == "solver.search"                     ? "--global"
                                       : key == "output.figure_format"              ? "--figures"
                                                                                    : "--tol");
  }
  overrides.insert(overrides.end(), o.set.begin(), o.set.end());
  try {
    apply_overrides(scene, overrides);
  } catch (const InputError& e) {
    for (const auto& [set, flag] : flags)
      if (e.where() == set && std::none_of(o.set.begin(), o.set.end(), [&, &set = set](const std::string& kv) {
            return "--set " + kv.substr(0, kv.find('=')) == set;
          })) {
        std::string m = e.detail();
        for (const auto& [other, name] : flags)  // "--set solver.tolerance" within the message: the flag
          for (auto at = m.find(other); at != std::string::npos; at = m.find(other))
            m.replace(at, other.size(), name);
        throw InputError(m, flag);
      }
    throw;
  }
  if (o.adapt && !scene.adapt) scene.adapt = SceneAdapt{};
  return scene;
}

namespace {

/// Several processes started by an MPI launcher share the outputs: only an engine that runs
/// across them does (mumps-mpi, a static solve; petsc-gamg and petsc-hypre on the full-space
/// route, any solve, which "auto" takes there: choose_route), and rank 0 writes
/// (docs/cluster.md). `as_given`: choose_route's.
void require_one_process_or_an_engine_across(const Scene& given, bool as_given) {
  const LaunchedProcesses launched = launched_processes();
  if (launched.size <= 1) return;
  const Scene scene = choose_route(given, {}, as_given);
  if (same_engine(scene.solver.linear, "mumps-mpi")) return;
  if (runs_across_processes(scene.solver.linear)) return;
  const std::string started = "started as " + std::to_string(launched.size) + " processes by an MPI launcher";
  const std::string why_not_across = same_engine(scene.solver.linear, "auto")
                                         ? " here (\"auto\" runs across processes on the full-space route, where "
                                           "petsc-gamg or petsc-hypre is built, only with the minimizer ssn, a local "
                                           "search and no --export-reduced)"
                                         : "";
  throw InputError(started + ", but the linear engine '" + scene.solver.linear + "' runs in one process" +
                       why_not_across +
                       " (the processes would race on the same outputs); use --linear mumps-mpi, "
                       "or petsc-gamg or petsc-hypre (the full-space route), or run without mpirun",
                   "--linear");
}

/// What run_solve tells while it works: iterations (-v), the problem's size, the steps of a
/// path or of an adaptive sequence, the global search.
RunOptions run_options(const SolveOptions& o, std::ostream& err) {
  RunOptions r;
  r.reduced_key = "--export-reduced";
  // under an MPI launcher rank 0 tells (the iterations of the full-space route run on every rank)
  if (o.json || o.verbosity < 1 || !reporting_process()) return r;
  if (o.verbosity >= 2)
    r.callback = [&err](const IterationRecord& i) {
      err << "  iteration " << i.iteration << ": F = " << std::setprecision(12) << i.objective << ", primal "
          << sci(i.primal, 3) << ", dual " << sci(i.dual, 3) << ", at bound " << i.active << "\n";
      return true;
    };
  r.on_built = [&err](const BuiltSummary& b) {
    if (!b.holds_results) return;
    err << "hemivem: " << b.vertices << " vertices, " << b.cells
        << (b.dimension == 3 ? " cells (three-dimensional)" : " elements") << "; solving with " << b.linear << " and "
        << b.minimizer << "\n";
  };
  r.progress = [&err](const GlobalSearchProgress& g) { err << progress_line(g) << "\n"; };
  r.on_path_step = [&err](const PathProgress& p) { err << p.line << "\n"; };
  r.on_adapt_step = [&err](const AdaptStep& a) { err << adapt_progress_line(a) << "\n"; };
  r.on_coarser_grid = [&err](const nlohmann::json& g) { err << "hemivem: coarser grid " << coarser_grid_text(g) << "\n"; };
  return r;
}

/// The lines after the full report: the files written, skipped and removed, the reduced problem.
void print_files(std::ostream& out, const SolveOptions& o, const OutputReport& report) {
  out << "  wrote         " << o.out << "/ (";
  for (std::size_t i = 0; i < report.written.size(); ++i) out << (i ? ", " : "") << report.written[i].filename().string();
  out << ")\n";
  for (const auto& s : report.skipped) out << "  skipped       " << s << "\n";
  if (!report.removed.empty()) {
    out << "  removed       ";
    for (std::size_t i = 0; i < report.removed.size(); ++i) out << (i ? ", " : "") << report.removed[i];
    out << " (an earlier run's, not written by this one)\n";
  }
  if (!o.export_reduced.empty()) out << "  reduced       " << o.export_reduced << "/\n";
}

/// The flags a kind of run cannot take, named by flag (run_scene names the scene's keys).
void check_flags_for(const SolveOptions& o, RunKind kind) {
  if (kind == RunKind::static_solve || !o.linear || !same_engine(*o.linear, "mumps-mpi")) return;
  throw InputError(kind == RunKind::path ? "a loading path runs in one process; the linear engine mumps-mpi runs across "
                                           "processes: choose another engine"
                                         : "an adaptive solve runs in one process; the linear engine mumps-mpi runs "
                                           "across processes: choose another engine",
                   "--linear");
}

}  // namespace

Scene load_pairs_scene(const std::string& scene, std::optional<int> n, std::optional<double> tolerance,
                       const std::vector<std::string>& set) {
  SolveOptions so;
  so.scene = scene;
  so.n = n;
  so.tolerance = tolerance;
  so.set = set;
  return load_scene(so);
}

int run_solve(const SolveOptions& o, std::ostream& out, std::ostream& err) {
  const Scene scene = load_scene(o);
  check_flags_for(o, run_kind(scene));
  check_output_folder(o.out);
  say_what_an_interruption_keeps(o.out);
  require_one_process_or_an_engine_across(scene, !o.export_reduced.empty());
  if (!o.export_reduced.empty() && is_krylov_solver(scene.solver.linear))
    throw InputError("the full-space route (linear engine " + scene.solver.linear +
                         ") poses no reduced problem: export it with a linear engine that factorizes",
                     "--export-reduced");
  ReducedProblem reduced;
  RunOptions options = run_options(o, err);
  options.reduced = o.export_reduced.empty() ? nullptr : &reduced;
  options.out = o.out;  // a path writes its steps there as it solves them
  const SceneRun run = run_scene(scene, std::move(options));
  if (!run.holds_results()) {  // rank > 0: its piece of the solution where the mesh was made in pieces; rank 0 reports
    run.write(o.out);
    return run.converged() ? kSuccess : kNotConverged;
  }
  if (!o.export_reduced.empty()) {
    if (!run.has_contact()) throw InputError("the scene has no contact boundary: there is no reduced problem", "--export-reduced");
    write_reduced_problem(o.export_reduced, reduced);
  }
  RunInfo info = run.info();
  for (const auto& w : info.warnings) err << "hemivem: warning: " << w << "\n";
  const OutputReport report = run.write(o.out);
  for (const auto& w : report.warnings) err << "hemivem: warning: " << w << "\n";  // a figure not drawn
  for (const auto& f : report.written) info.files.push_back(f.filename().string());
  if (o.json) {
    nlohmann::json j = run.result_json(info.files);
    for (const auto& w : report.warnings) j["warnings"].push_back(w);  // as result.json records them
    out << j.dump(2) << "\n";
  } else if (o.verbosity >= 1) {
    out << "hemivem solve: " << scene.title << " (" << scene.source << ")\n" << run.report(info);
    print_files(out, o, report);
  }
  return run.converged() ? kSuccess : kNotConverged;
}

namespace {

/// The names of a reduced problem's laws, law 0 first.
std::vector<std::string> law_names(const ReducedProblem& p) {
  std::vector<std::string> names;
  for (int k = 0; k < p.num_laws(); ++k) names.push_back(p.law_by_number(k).name());
  return names;
}

}  // namespace

int run_minimize(const MinimizeOptions& o, std::ostream& out, std::ostream& err) {
  const ReducedProblem p = read_reduced_problem(o.folder, o.law.empty() ? nullptr : make_contact_law(o.law));
  const std::optional<UniformForm> uniform = p.uniform_form();
  std::unique_ptr<NonsmoothMinimizer> minimizer = make_minimizer(o.minimizer);
  if (o.global) {
    GlobalSearchOptions go = o.search;
    if (o.verbosity >= 1 && !o.json) go.progress = [&](const GlobalSearchProgress& g) { err << progress_line(g) << "\n"; };
    minimizer = make_global_search(std::move(minimizer), std::move(go), o.engines);
  }
  MinimizerOptions mo;
  mo.tolerance = o.tolerance;
  const MinimizerResult r = minimizer->minimize(p, Eigen::VectorXd(), mo);
  if (o.json) {
    nlohmann::json j;
    j["schema"] = "hemivem-minimize/3";
    j["minimizer"] = first_engine(*minimizer);
    j["search"] = search_json(*minimizer);
    j["critical_points"] = critical_points_json(r, 0.0);
    j["law"] = p.law_by_number(0).name();
    j["laws"] = law_names(p);
    j["constraint"] = uniform ? to_string(uniform->constraint) : std::string("coordinate-wise");
    j["size"] = p.size();
    j["status"] = to_string(r.status);
    j["converged"] = r.converged();
    j["message"] = r.message;
    j["certificate"] = certificate_json(r.certificate);
    j["reduced_objective"] = number(r.objective);
    j["iterations"] = r.iterations;
    j["evaluations"] = {{"function", r.function_evaluations}, {"subgradient", r.subgradient_evaluations}};
    j["may_be_nonunique"] = r.may_be_nonunique;
    j["uniqueness_margin"] = number(p.uniqueness_margin);
    j["uniqueness_roundoff"] = number(p.uniqueness_roundoff);
    j["uniqueness"] = uniqueness_verdict(p.uniqueness_margin);
    j["timings"] = r.timings;
    auto array = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
    j["a"] = array(r.a);
    j["law_force"] = array(r.law_force);
    j["reaction"] = array(r.reaction);
    out << j.dump(2) << "\n";
  } else if (o.verbosity >= 1) {
    std::string laws;
    for (const auto& name : law_names(p)) laws += (laws.empty() ? "" : ", ") + name;
    out << std::setprecision(12) << "hemivem minimize: " << o.folder << " (" << p.size()
        << (uniform ? " contact nodes, law " + laws + ", constraint " + to_string(uniform->constraint) + ")\n"
                    : " unknowns, laws " + laws + ", bounds per coordinate)\n")
        << "  minimizer     " << first_engine(*minimizer) << (o.global ? " (global search)" : "") << "\n"
        << "  status        " << to_string(r.status) << " (certificate: " << certificate_text(r.certificate) << "), "
        << r.iterations << " iterations, "
        << r.function_evaluations << " + " << r.subgradient_evaluations << " evaluations\n"
        << "  F(a)          " << r.objective << "\n"
        << "  time [s]      " << (r.timings.count("total") ? r.timings.at("total") : 0.0) << "\n";
    if (o.global) out << critical_points_text(r, 0.0);
    out << "  uniqueness    lambda_min(S - alpha_j W) = " << p.uniqueness_margin << ": "
        << uniqueness_meaning(p.uniqueness_margin) << "\n";
  }
  return r.converged() ? kSuccess : kNotConverged;
}

}  // namespace hemivem::cli
