#include "commands.hpp"

#include <hemivem/contact_solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/process_group.hpp>
#include <hemivem/piecewise_law.hpp>
#include <hemivem/reduced_io.hpp>
#include <hemivem/scene.hpp>

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
#include "outputs.hpp"

namespace hemivem::cli {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string toml_string(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

}  // namespace

Scene load_scene(const SolveOptions& o) {
  Scene scene = o.scene.empty() ? default_scene() : parse_scene(o.scene);
  // every flag and --set at once: validated together, in no particular order
  std::vector<std::string> overrides;
  if (o.mesh) {
    const std::string ext = std::filesystem::path(*o.mesh).extension().string();
    const bool file = o.mesh->find('/') != std::string::npos || !ext.empty();
    const auto& kinds = mesh_generator_names();
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
  overrides.insert(overrides.end(), o.set.begin(), o.set.end());
  apply_overrides(scene, overrides);
  return scene;
}

double SceneSolve::total_seconds() const {
  const auto it = solution.timings.find("total");
  return mesh_seconds + (it == solution.timings.end() ? 0.0 : it->second);
}

bool same_engine(const std::string& a, const std::string& b) { return normalized_engine_name(a) == normalized_engine_name(b); }

std::unique_ptr<NonsmoothMinimizer> make_scene_minimizer(const Scene& scene, const std::string& name) {
  if (scene.solver.parameters.empty() || !same_engine(name, scene.solver.minimizer)) return make_minimizer(name);
  try {
    return make_minimizer(name, scene.solver.parameters);
  } catch (const InputError& e) {
    throw InputError("solver.parameters: minimizer '" + e.where() + "': " + e.detail(), scene.where("solver.parameters"));
  }
}

std::unique_ptr<NonsmoothMinimizer> make_scene_search(const Scene& scene,
                                                      std::function<void(const GlobalSearchProgress&)> progress) {
  auto first = make_scene_minimizer(scene, scene.solver.minimizer);
  if (scene.solver.search != "global") return first;
  GlobalSearchOptions go;
  go.max_starts = scene.solver.max_starts;
  go.time_budget = scene.solver.time_budget;
  go.seed = scene.solver.seed;
  go.progress = std::move(progress);
  try {
    return make_global_search(std::move(first), std::move(go), scene.solver.search_engines);
  } catch (const InputError& e) {
    throw InputError("solver.search_engines: " + e.detail(), scene.where("solver.search_engines"));
  }
}

namespace {
/// The engine a minimizer stands for: itself, or the first engine of a global search.
std::string first_engine(const NonsmoothMinimizer& m) {
  const auto* g = dynamic_cast<const GlobalSearch*>(&m);
  return g ? g->engine_names().front() : m.name();
}
}  // namespace

nlohmann::json search_json(const NonsmoothMinimizer& minimizer) {
  const auto* search = dynamic_cast<const GlobalSearch*>(&minimizer);
  if (!search) return {{"kind", "local"}};
  const GlobalSearchOptions& go = search->options();
  return {{"kind", "global"},
          {"engines", search->engine_names()},
          {"max_starts", go.max_starts},
          {"time_budget", go.time_budget},
          {"seed", go.seed},
          {"random_starts", go.random_starts},
          {"agree", go.agree}};
}

SceneSolve solve_scene(const Scene& scene, const std::function<void(const BuiltProblem&, const SceneSolve&)>& on_built,
                       std::function<bool(const IterationRecord&)> callback, ReducedProblem* reduced,
                       std::function<void(const GlobalSearchProgress&)> progress) {
  // Engines first: a name that was not built is an input error before any work.
  SceneSolve s;
  FactorizationOptions fo;
  fo.engine = scene.solver.linear;
  auto factorization = make_factorization(fo);
  const auto minimizer = make_scene_search(scene, std::move(progress));
  s.linear = factorization->name();
  s.minimizer = first_engine(*minimizer);
  s.search = search_json(*minimizer);
  s.holds_results = processes_of(*factorization).holds_results();
  s.processes = processes_of(*factorization).num_processes();
  s.options.tolerance = scene.solver.tolerance;
  s.options.max_iterations = scene.solver.max_iterations;
  s.options.callback = std::move(callback);

  const auto t = Clock::now();
  s.built = build_problem(scene);
  s.mesh_seconds = since(t);
  if (on_built) on_built(*s.built, s);
  s.solution = solve_contact(s.built->problem, std::move(factorization), *minimizer, s.options, reduced);
  return s;
}

std::vector<std::string> wanted_files(const Scene& scene, bool has_contact) {
  static const std::vector<std::pair<std::string, std::string>> map{
      {"result-json", "result.json"}, {"contact-csv", "contact.csv"}, {"displacement-csv", "displacement.csv"},
      {"history-csv", "history.csv"}, {"vtu", "solution.vtu"},        {"u-nu-png", "u_nu.png"},
      {"deformed-png", "deformed.png"}};
  std::vector<std::string> files;
  for (const auto& [name, file] : map) {
    if (!has_contact && (file == "contact.csv" || file == "history.csv" || file == "u_nu.png")) continue;
    if (std::find(scene.outputs.begin(), scene.outputs.end(), name) != scene.outputs.end()) files.push_back(file);
  }
  files.push_back("scene.toml");
  return files;
}

RunInfo run_info(const Scene& scene, const SceneSolve& solved) {
  const BuiltProblem& built = *solved.built;
  const MinimizerOptions& mo = solved.options;
  RunInfo info;
  info.scene_name = scene.title;
  info.scene_toml = to_toml(scene);
  info.mesh = scene.mesh.description();
  info.linear = solved.linear;
  info.minimizer = solved.minimizer;
  info.search = solved.search;
  info.options = {{"tolerance", mo.tolerance},
                  {"max_iterations", mo.max_iterations},
                  {"stabilization", to_string(scene.material.stabilization)},
                  {"plane_model", to_string(scene.material.model)},
                  {"scene", scene.source}};
  info.mesh_seconds = solved.mesh_seconds;
  info.dofs = solved.solution.unknowns;
  info.processes = solved.processes;
  info.warnings = built.warnings;
  if (built.problem.law) info.law_breakpoints = built.problem.law->breakpoints();
  info.gap_bound = built.has_contact && (built.problem.constraint == ConstraintKind::one_sided ||
                                         built.problem.constraint == ConstraintKind::box);
  if (built.problem.friction) info.friction_law = built.problem.friction->name();
  if (built.problem.constraint == ConstraintKind::bilateral) info.law_breakpoints.clear();
  return info;
}

int run_solve(const SolveOptions& o, std::ostream& out, std::ostream& err) {
  const Scene scene = load_scene(o);
  check_output_folder(o.out);
  // ---- runs across processes (docs/cluster.md) ----
  if (const LaunchedProcesses launched = launched_processes(); launched.size > 1) {
    if (!same_engine(scene.solver.linear, "mumps-mpi"))
      throw InputError("started as " + std::to_string(launched.size) + " processes by an MPI launcher, but the linear engine '" +
                           scene.solver.linear + "' runs in one process (the processes would race on the same outputs); use "
                           "--linear mumps-mpi, or run without mpirun",
                       "--linear");
  }
  // ---- end runs across processes ----
  std::function<bool(const IterationRecord&)> callback;
  if (o.verbosity >= 2 && !o.json)
    callback = [&](const IterationRecord& r) {
      err << "  iteration " << r.iteration << ": F = " << std::setprecision(12) << r.objective << ", primal "
          << sci(r.primal, 3) << ", dual " << sci(r.dual, 3) << ", at bound " << r.active << "\n";
      return true;
    };
  auto announce = [&](const BuiltProblem& built, const SceneSolve& s) {
    if (o.verbosity >= 1 && !o.json && s.holds_results)
      err << "hemivem: " << built.mesh.num_vertices() << " vertices, " << built.mesh.num_elements()
          << " elements; solving with " << s.linear << " and " << s.minimizer << "\n";
  };
  std::function<void(const GlobalSearchProgress&)> progress;
  if (o.verbosity >= 1 && !o.json) progress = [&](const GlobalSearchProgress& p) { err << progress_line(p) << "\n"; };
  ReducedProblem reduced;
  SceneSolve solved =
      solve_scene(scene, announce, callback, o.export_reduced.empty() ? nullptr : &reduced, std::move(progress));
  const auto& built = solved.built;
  const ContactSolution& sol = solved.solution;
  if (!solved.holds_results) return sol.converged() ? kSuccess : kNotConverged;  // rank > 0: rank 0 reports
  const double mesh_seconds = solved.mesh_seconds;
  if (!o.export_reduced.empty()) {
    if (!built->has_contact) throw InputError("the scene has no contact boundary: there is no reduced problem", "--export-reduced");
    write_reduced_problem(o.export_reduced, reduced);
  }

  RunInfo info = run_info(scene, solved);
  for (const auto& w : info.warnings) err << "hemivem: warning: " << w << "\n";
  const OutputReport report = write_outputs(o.out, built->mesh, built->problem.elasticity.materials, sol, info,
                                            wanted_files(scene, built->has_contact));
  for (const auto& f : report.written) info.files.push_back(f.filename().string());

  if (o.json) {
    out << result_json(built->mesh, sol, info).dump(2) << "\n";
  } else if (o.verbosity >= 1) {
    const auto& r = sol.minimizer;
    int upper = 0, lower = 0;
    for (const auto& c : sol.contact) upper += c.state == "upper", lower += c.state == "lower";
    out << std::setprecision(6);
    out << "hemivem solve: " << scene.title << " (" << scene.source << ")\n"
        << "  mesh          " << info.mesh << ": " << built->mesh.num_vertices() << " vertices, "
        << built->mesh.num_elements() << " elements, h = " << built->mesh.h() << ", " << info.dofs << " unknowns\n"
        << "  engines       linear " << info.linear
        << (info.processes > 1 ? " (" + std::to_string(info.processes) + " processes)" : std::string())
        << (built->has_contact ? ", minimizer " + info.minimizer : std::string(" (no contact: one linear solve)"))
        << "\n"
        << "  stages        ";
    for (std::size_t i = 0; i < sol.stages.size(); ++i) out << (i ? ", " : "") << sol.stages[i];
    out << "\n  status        " << to_string(r.status) << " (certificate: " << certificate_text(r.certificate) << "), "
        << r.iterations << " iterations\n";
    if (info.search.value("kind", "local") == "global") out << critical_points_text(r, sol.energy - r.objective);
    if (!sol.contact.empty()) {
      out << "  uniqueness    lambda_min(S - alpha_j W) = " << sol.uniqueness_margin
          << (sol.uniqueness_margin > 0 ? " > 0: the solution is unique\n"
                                        : " <= 0: several critical points are possible; this is one of them\n")
          << "  contact       " << sol.contact.size() << " nodes: ";
      if (scene.contact && scene.contact->constraint == ConstraintKind::bilateral) {
        out << "u_nu = 0 (bilateral)\n";
      } else {
        out << upper << " at the upper bound, ";
        if (scene.contact && scene.contact->constraint == ConstraintKind::box) out << lower << " at the lower bound, ";
        out << sol.contact.size() - upper - lower << " free\n";
      }
      double law = 0.0, reaction = 0.0, friction = 0.0;
      std::map<std::string, int> states;
      for (const auto& c : sol.contact) law += c.law_force, reaction += c.reaction, friction += c.friction_force;
      for (const auto& c : sol.contact)
        if (!c.friction_state.empty()) ++states[c.friction_state];
      out << "  forces        contact force " << law + reaction << " in total: law " << law << ", reactions "
          << reaction << "\n";
      if (!states.empty()) {
        out << "  friction      " << (info.friction_law.empty() ? std::string("none") : info.friction_law) << ": ";
        bool first = true;
        for (const auto& [state, count] : states) out << (first ? "" : ", ") << count << " " << state, first = false;
        out << "; friction force " << friction << " in total\n";
      }
    }
    out << "  energy        potential " << sol.energy << "\n  time [s]      mesh " << mesh_seconds;
    for (const char* k : {"assembly", "linear_solve", "condensation", "minimize", "back_substitution"})
      if (sol.timings.count(k)) out << ", " << k << " " << sol.timings.at(k);
    out << ", total " << mesh_seconds + sol.timings.at("total") << "\n  wrote         " << o.out << "/ (";
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
  return sol.converged() ? kSuccess : kNotConverged;
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
    if (r.may_be_nonunique) out << "  note          uniqueness is not guaranteed (margin not positive or unknown)\n";
  }
  return r.converged() ? kSuccess : kNotConverged;
}

}  // namespace hemivem::cli
