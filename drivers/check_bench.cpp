#include "check_bench.hpp"

#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene.hpp>

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
#include "outputs.hpp"
#include "plots.hpp"

namespace hemivem::cli {

namespace fs = std::filesystem;

namespace {

struct Pair {
  std::string linear, minimizer;
  std::string label() const { return linear + "+" + minimizer; }
};

// Every built pair, linear engine major. mumps-mpi is included: the factory runs it as one
// process (one MPI rank), which needs no launcher.
std::vector<Pair> available_pairs() {
  std::vector<Pair> pairs;
  for (const auto& l : available_factorizations())
    for (const auto& m : available_minimizers()) pairs.push_back({l, m});
  return pairs;
}

// What one pair did on one scene.
struct PairRun {
  Pair pair;
  bool failed = false;        ///< an engine threw (NumericalError): no solution
  std::string status = "failed";
  std::string message;
  bool converged = false;
  Certificate certificate;
  int iterations = 0;
  double margin = std::numeric_limits<double>::quiet_NaN();  ///< lambda_min(S - alpha_j W)
  double mesh_seconds = 0.0;
  std::map<std::string, double> timings;
  double seconds = 0.0;       ///< total wall time: mesh + solve
  int vertices = 0;
  int contact_nodes = 0;
  Eigen::VectorXd u;
  std::unique_ptr<BuiltProblem> built;  ///< the mesh and problem solved (null when failed)
};

PairRun run_pair(const Scene& base, const Pair& pair) {
  Scene scene = base;
  scene.solver.linear = pair.linear;
  scene.solver.minimizer = pair.minimizer;
  // [solver.parameters] belong to the scene's own minimizer; the others keep their defaults
  if (!same_engine(pair.minimizer, base.solver.minimizer)) scene.solver.parameters.clear();
  PairRun r;
  r.pair = pair;
  try {
    SceneSolve s = solve_scene(scene);
    const auto& m = s.solution.minimizer;
    r.status = to_string(m.status);
    r.message = m.message;
    r.converged = s.solution.converged();
    r.certificate = m.certificate;
    r.iterations = m.iterations;
    r.margin = s.solution.uniqueness_margin;
    r.mesh_seconds = s.mesh_seconds;
    r.timings = s.solution.timings;
    r.seconds = s.total_seconds();
    r.vertices = s.built->mesh.num_vertices();
    r.contact_nodes = static_cast<int>(s.solution.contact.size());
    r.u = std::move(s.solution.u);
    r.built = std::move(s.built);
  } catch (const NumericalError& e) {
    r.failed = true;
    r.message = e.what();
  }
  return r;
}

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

SolveOptions scene_options(const std::string& scene, std::optional<int> n, std::optional<double> tolerance,
                           const std::vector<std::string>& set) {
  SolveOptions so;
  so.scene = scene;
  so.n = n;
  so.tolerance = tolerance;
  so.set = set;
  return so;
}

std::string mesh_text(const Scene& s) { return s.mesh.description(); }

double stage(const PairRun& r, const std::string& name) {
  if (name == "mesh") return r.mesh_seconds;
  if (name == "total") return r.seconds;
  const auto it = r.timings.find(name);
  return it == r.timings.end() ? 0.0 : it->second;
}

// The stages of the terminal table; the files also have linear_solve (the single solve of a
// scene without contact).
const std::vector<std::string>& stage_names() {
  static const std::vector<std::string> names{"mesh", "assembly", "condensation", "minimize", "back_substitution", "total"};
  return names;
}
const std::vector<std::string>& file_stage_names() {
  static const std::vector<std::string> names{"mesh",     "assembly",          "linear_solve", "condensation",
                                              "minimize", "back_substitution", "total"};
  return names;
}

}  // namespace

// ---- check -------------------------------------------------------------------------

int run_check(const CheckOptions& o, std::ostream& out, std::ostream& err) {
  if (!(o.agree > 0.0)) throw InputError("must be > 0", "--agree");
  const Scene base = load_scene(scene_options(o.scene, o.n, o.tolerance, o.set));
  const std::vector<Pair> pairs = available_pairs();
  const bool progress = o.verbosity >= 1;

  std::vector<PairRun> runs;
  for (const auto& p : pairs) {
    if (progress) err << "hemivem check: " << std::left << std::setw(28) << p.label() << std::flush;
    runs.push_back(run_pair(base, p));
    if (progress) err << runs.back().status << " (" << fixed(runs.back().seconds, 3) << " s)\n";
  }

  // The scale: max |u| of the reference pair eigen+ssn (else the largest converged one).
  double scale = 0.0;
  for (const auto& r : runs)
    if (r.pair.linear == "eigen" && r.pair.minimizer == "ssn" && !r.failed) scale = max_abs(r.u);
  if (scale == 0.0)
    for (const auto& r : runs)
      if (r.converged) scale = std::max(scale, max_abs(r.u));
  if (scale == 0.0) scale = 1.0;  // no displacement at all: absolute differences

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
  double margin = nan;
  for (const auto& r : runs)
    if (!r.failed && !std::isnan(r.margin)) margin = std::isnan(margin) ? r.margin : std::max(margin, r.margin);
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

  if (o.json) {
    nlohmann::json j;
    j["schema"] = "hemivem-check/2";
    j["version"] = HEMIVEM_VERSION;
    j["scene"] = base.title;
    j["source"] = base.source;
    j["mesh"] = mesh_text(base);
    j["tolerance"] = base.solver.tolerance;
    j["agree"] = o.agree;
    j["uniqueness_margin"] = number(margin);
    j["unique"] = unique;
    j["reference"] = {{"linear", "eigen"}, {"minimizer", "ssn"}, {"max_abs_u", scale}};
    j["pairs"] = nlohmann::json::array();
    for (std::size_t i = 0; i < np; ++i) {
      const auto& r = runs[i];
      j["pairs"].push_back({{"linear", r.pair.linear},
                            {"minimizer", r.pair.minimizer},
                            {"status", r.status},
                            {"converged", r.converged},
                            {"message", r.message},
                            {"certificate", certificate_json(r.certificate)},
                            {"iterations", r.iterations},
                            {"seconds", r.seconds},
                            {"max_difference", number(pair_max[i])}});
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
    j["verdict"] = verdict.str();
    j["exit_code"] = code;
    out << j.dump(2) << "\n";
  } else if (o.verbosity >= 1) {
    out << "hemivem check: " << base.title << " (" << base.source << "), " << mesh_text(base);
    if (!runs.empty()) out << ": " << runs.front().vertices << " vertices, " << runs.front().contact_nodes << " contact nodes";
    out << "\n  tolerance " << sci(base.solver.tolerance) << ", agree " << sci(o.agree)
        << "; differences are max|u_a - u_b| / max|u_ref|, u_ref from eigen+ssn (max|u_ref| = " << sci(scale, 4)
        << ")\n  " << margin_text
        << (unique ? ": the solution is unique, converged pairs must agree\n\n"
                   : ": several critical points are possible, differences between converged pairs are reported "
                     "but are not a disagreement\n\n");
    out << std::left << std::setw(4) << "  #" << std::setw(10) << "linear" << std::setw(18) << "minimizer"
        << std::setw(17) << "status" << std::right << std::setw(10) << "primal" << std::setw(10) << "dual"
        << std::setw(7) << "iter" << std::setw(10) << "time [s]" << std::setw(11) << "max diff" << "\n";
    for (std::size_t i = 0; i < np; ++i) {
      const auto& r = runs[i];
      out << std::right << std::setw(3) << i + 1 << " " << std::left << std::setw(10) << r.pair.linear << std::setw(18)
          << r.pair.minimizer << std::setw(17) << r.status << std::right << std::setw(10) << sci(r.certificate.primal)
          << std::setw(10) << sci(r.certificate.dual) << std::setw(7) << r.iterations << std::setw(10) << fixed(r.seconds)
          << std::setw(11) << sci(pair_max[i]) << "\n";
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

// ---- bench -------------------------------------------------------------------------

Eigen::VectorXd interpolate_squares(const Mesh& mesh, const Eigen::VectorXd& u, int n,
                                    const std::array<double, 4>& domain, const std::vector<Vec2>& points) {
  const double x0 = domain[0], y0 = domain[2];
  const double hx = (domain[1] - domain[0]) / n, hy = (domain[3] - domain[2]) / n;
  const int side = n + 1;
  if (mesh.num_vertices() != side * side || u.size() != 2 * mesh.num_vertices())
    throw InputError("not a squares mesh with n = " + std::to_string(n), "interpolate_squares");
  std::vector<int> grid(static_cast<std::size_t>(side * side), -1);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double fi = (mesh.vertex(v).x() - x0) / hx, fj = (mesh.vertex(v).y() - y0) / hy;
    const long i = std::lround(fi), j = std::lround(fj);
    if (std::abs(fi - i) > 1e-6 || std::abs(fj - j) > 1e-6 || i < 0 || j < 0 || i > n || j > n)
      throw InputError("vertex " + std::to_string(v) + " is not on the squares grid", "interpolate_squares");
    grid[static_cast<std::size_t>(j * side + i)] = v;
  }
  if (std::count(grid.begin(), grid.end(), -1) != 0)
    throw InputError("the squares grid has a missing vertex", "interpolate_squares");
  auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(j * side + i)]; };

  Eigen::VectorXd r(2 * static_cast<Eigen::Index>(points.size()));
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double fx = (points[k].x() - x0) / hx, fy = (points[k].y() - y0) / hy;
    const int i = std::clamp(static_cast<int>(std::floor(fx)), 0, n - 1);
    const int j = std::clamp(static_cast<int>(std::floor(fy)), 0, n - 1);
    const double s = fx - i, t = fy - j;
    const double w[4] = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
    const int v[4] = {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)};
    for (int c = 0; c < 2; ++c) {
      double value = 0.0;
      for (int q = 0; q < 4; ++q) value += w[q] * u(2 * v[q] + c);
      r(2 * static_cast<Eigen::Index>(k) + c) = value;
    }
  }
  return r;
}

namespace {

struct BenchRow {
  PairRun run;
  int n = 0;
  double error = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not defined (not squares)
};

// The work-precision figure: one series per pair, log error (x) against log total time (y).
// Empty on success, else why it was skipped.
std::string bench_plot(const fs::path& dir, const std::vector<Pair>& pairs, const std::vector<BenchRow>& rows) {
  std::ostringstream script;
  script << std::setprecision(17);
  std::vector<std::string> series;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    std::ostringstream block;
    block << std::setprecision(17);
    int points = 0;
    for (const auto& r : rows)
      if (r.run.pair.label() == pairs[p].label() && std::isfinite(r.error) && r.error > 0.0 && r.run.seconds > 0.0) {
        block << r.error << ' ' << r.run.seconds << ' ' << r.n << '\n';
        ++points;
      }
    if (!points) continue;
    script << "$d" << p << " << EOD\n" << block.str() << "EOD\n";
    // colour by minimizer, dash and point type by linear engine
    const auto linear = available_factorizations();
    const auto minimizers = available_minimizers();
    const auto li = static_cast<std::size_t>(std::find(linear.begin(), linear.end(), pairs[p].linear) - linear.begin());
    const auto mi = static_cast<std::size_t>(std::find(minimizers.begin(), minimizers.end(), pairs[p].minimizer) - minimizers.begin());
    series.push_back("$d" + std::to_string(p) + " using 1:2 with linespoints lw 2 ps 1.3 lc " + std::to_string(mi + 1) +
                     " dt " + std::to_string(li + 1) + " pt " + std::to_string(2 * li + 5) + " title " +
                     gnuplot_quote(pairs[p].label()));
  }
  if (series.empty()) return "no finite positive error to plot";
  script << "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\n"
         << "set xlabel 'relative error: max|I_h u_h - u_{ref}| / max|u_{ref}| (dimensionless)'\n"
         << "set ylabel 'wall time, whole solve (s)'\n"
         << "set title 'work against precision: every pair of engines on every mesh size'\nset grid\n"
         << "set key outside right top noenhanced\n"
         << "plot ";
  for (std::size_t i = 0; i < series.size(); ++i) script << (i ? ", \\\n     " : "") << series[i];
  Figure f;
  f.png = "bench.png";
  f.width = 1100;
  f.height = 750;
  f.script = script.str();
  return draw_figures(dir, {f}).front();
}

}  // namespace

int run_bench(const BenchOptions& o, std::ostream& out, std::ostream& err) {
  if (o.n.empty()) throw InputError("give at least one mesh size", "--n");
  for (int n : o.n)
    if (n < 1) throw InputError("mesh sizes must be >= 1, got " + std::to_string(n), "--n");
  if (o.ref < 1) throw InputError("must be >= 1", "--ref");
  const Scene base = load_scene(scene_options(o.scene, std::nullopt, o.tolerance, o.set));
  // Every size is validated (a scene reading a mesh file refuses mesh.n) before any work.
  auto at_size = [&](int n) {
    Scene s = base;
    apply_override(s, "mesh.n=" + std::to_string(n));
    return s;
  };
  std::vector<Scene> scenes;
  for (int n : o.n) scenes.push_back(at_size(n));
  const bool squares = base.mesh.file.empty() && base.mesh.generator == "squares";
  const bool progress = o.verbosity >= 1;
  const std::vector<Pair> pairs = available_pairs();
  fs::create_directories(o.out);

  // The reference: the finest mesh, the exact active-set method on a direct solver.
  const auto linear = available_factorizations();
  const Pair ref_pair{std::find(linear.begin(), linear.end(), "cholmod") != linear.end() ? "cholmod" : "eigen", "ssn"};
  PairRun reference;
  std::vector<Vec2> ref_points;
  double ref_scale = 0.0;
  if (squares) {
    if (progress) err << "hemivem bench: reference " << ref_pair.label() << " at n = " << o.ref << " ... " << std::flush;
    reference = run_pair(at_size(o.ref), ref_pair);
    if (reference.failed) throw NumericalError("the reference " + ref_pair.label() + " failed: " + reference.message);
    ref_points = reference.built->mesh.vertices();
    reference.built.reset();
    ref_scale = max_abs(reference.u);
    if (ref_scale == 0.0) ref_scale = 1.0;
    if (progress) err << reference.status << " (" << fixed(reference.seconds, 3) << " s)\n";
  } else if (progress) {
    err << "hemivem bench: the scene's mesh is not squares: errors are not computed\n";
  }

  std::vector<BenchRow> rows;
  bool all_converged = !squares || reference.converged;
  for (const auto& p : pairs) {
    for (std::size_t k = 0; k < o.n.size(); ++k) {
      if (progress) err << "hemivem bench: " << std::left << std::setw(28) << p.label() << "n = " << std::setw(5) << o.n[k] << std::flush;
      BenchRow row;
      row.n = o.n[k];
      row.run = run_pair(scenes[k], p);
      if (squares && !row.run.failed) {
        const Eigen::VectorXd fine =
            interpolate_squares(row.run.built->mesh, row.run.u, o.n[k], scenes[k].mesh.domain, ref_points);
        row.error = max_abs(fine - reference.u) / ref_scale;
      }
      row.run.built.reset();
      all_converged &= row.run.converged;
      if (progress) err << row.run.status << " (" << fixed(row.run.seconds, 3) << " s), error " << sci(row.error) << "\n";
      rows.push_back(std::move(row));
    }
  }

  // bench.csv
  const fs::path csv = fs::path(o.out) / "bench.csv";
  write_atomically(csv, [&](std::ostream& os) {
    os << std::setprecision(10) << "linear,minimizer,n,vertices,contact_nodes,status,converged,iterations,primal,dual";
    for (const auto& s : file_stage_names()) os << ',' << s;
    os << ",error\n";
    for (const auto& r : rows) {
      os << r.run.pair.linear << ',' << r.run.pair.minimizer << ',' << r.n << ',' << r.run.vertices << ','
         << r.run.contact_nodes << ',' << r.run.status << ',' << (r.run.converged ? "true" : "false") << ','
         << r.run.iterations << ',';
      if (std::isfinite(r.run.certificate.primal)) os << r.run.certificate.primal;
      os << ',';
      if (std::isfinite(r.run.certificate.dual)) os << r.run.certificate.dual;
      for (const auto& s : file_stage_names()) os << ',' << stage(r.run, s);
      os << ',';
      if (std::isfinite(r.error)) os << r.error;
      os << '\n';
    }
  });

  // bench.json
  nlohmann::json j;
  j["schema"] = "hemivem-bench/2";
  j["version"] = HEMIVEM_VERSION;
  j["scene"] = base.title;
  j["source"] = base.source;
  j["mesh"] = base.mesh.file.empty() ? base.mesh.generator : base.mesh.file.string();
  j["tolerance"] = base.solver.tolerance;
  j["error_definition"] =
      squares ? "max over the reference vertices and both components of |I_h u_h - u_ref| / max|u_ref|, "
                "I_h the bilinear interpolation of the squares solution (exact prolongation for nested meshes)"
              : "not computed: the scene's mesh is not squares";
  if (squares)
    j["reference"] = {{"n", o.ref},
                      {"linear", ref_pair.linear},
                      {"minimizer", ref_pair.minimizer},
                      {"status", reference.status},
                      {"converged", reference.converged},
                      {"vertices", reference.vertices},
                      {"seconds", reference.seconds},
                      {"max_abs_u", ref_scale}};
  else
    j["reference"] = nullptr;
  j["rows"] = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json times;
    for (const auto& s : file_stage_names()) times[s] = stage(r.run, s);
    j["rows"].push_back({{"linear", r.run.pair.linear},
                         {"minimizer", r.run.pair.minimizer},
                         {"n", r.n},
                         {"vertices", r.run.vertices},
                         {"contact_nodes", r.run.contact_nodes},
                         {"status", r.run.status},
                         {"converged", r.run.converged},
                         {"message", r.run.message},
                         {"iterations", r.run.iterations},
                         {"certificate", certificate_json(r.run.certificate)},
                         {"seconds", times},
                         {"error", number(r.error)}});
  }
  const std::string plot_failure = bench_plot(o.out, pairs, rows);
  j["plot"] = plot_failure.empty() ? nlohmann::json("bench.png") : nlohmann::json(nullptr);
  if (!plot_failure.empty()) j["plot_skipped"] = plot_failure;
  write_atomically(fs::path(o.out) / "bench.json", [&](std::ostream& os) { os << j.dump(2) << "\n"; });

  if (o.json) {
    out << j.dump(2) << "\n";
  } else if (o.verbosity >= 1) {
    out << "hemivem bench: " << base.title << " (" << base.source << ")";
    if (squares)
      out << "; reference " << ref_pair.label() << " on squares n = " << o.ref << " (" << reference.status << ", "
          << fixed(reference.seconds, 3) << " s)";
    out << "\n  times in seconds; error = max|I_h u_h - u_ref| / max|u_ref| at the reference vertices\n\n";
    out << std::left << std::setw(10) << "linear" << std::setw(18) << "minimizer" << std::right << std::setw(5) << "N"
        << "  " << std::left << std::setw(16) << "status" << std::right;
    for (const char* h : {"mesh", "assembly", "condense", "minimize", "back-sub", "total"}) out << std::setw(10) << h;
    out << std::setw(11) << "error" << "\n";
    for (const auto& r : rows) {
      out << std::left << std::setw(10) << r.run.pair.linear << std::setw(18) << r.run.pair.minimizer << std::right
          << std::setw(5) << r.n << "  " << std::left << std::setw(16) << r.run.status << std::right;
      for (const auto& s : stage_names()) out << std::setw(10) << fixed(stage(r.run, s));
      out << std::setw(11) << (std::isfinite(r.error) ? sci(r.error) : std::string("null")) << "\n";
    }
    out << "\n  wrote     " << o.out << "/ (bench.csv, bench.json" << (plot_failure.empty() ? ", bench.png" : "")
        << ")\n";
    if (!plot_failure.empty()) out << "  skipped   bench.png: " << plot_failure << "\n";
  }
  return all_converged ? kSuccess : kNotConverged;
}

}  // namespace hemivem::cli
