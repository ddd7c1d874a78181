#include <hemivem/app/study.hpp>

#include <hemivem/error.hpp>
#include <hemivem/support/output_folder.hpp>
#include <hemivem/vem/bilinear.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include <hemivem/app/format.hpp>
#include <hemivem/app/solve.hpp>

namespace hemivem::app {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// docs/table1.md: the paper's Table 1 and what an independent implementation of its section 2
// gives (relative energy error against the N = 256 solution), by N.
std::optional<double> paper_value(int n) {
  switch (n) {
    case 4: return 0.5207;
    case 8: return 0.3067;
    case 16: return 0.1789;
    case 32: return 0.1031;
    case 64: return 0.05602;
    default: return std::nullopt;
  }
}
std::optional<double> independent_value(int n) {
  switch (n) {
    case 4: return 0.3626;
    case 8: return 0.2250;
    case 16: return 0.1369;
    case 32: return 0.0817;
    case 64: return 0.0468;
    case 128: return 0.0237;
    default: return std::nullopt;
  }
}

constexpr const char* kNote =
    "the paper's Table 1 column is not reproduced (neither here nor by the independent implementation of "
    "its section 2, docs/table1.md); the independent column is what that implementation gives";

// The values of docs/table1.md belong to Example 4.1: the default scene up to the mesh size, the
// engines, the outputs and the two material choices whose effect the study is used to show
// (stabilization weight, plane model).
bool is_example_41(const Scene& scene) {
  const Scene d = default_scene();
  Scene s = scene;
  s.title = d.title;
  s.mesh.n = d.mesh.n;
  s.mesh.ny = d.mesh.ny;
  s.mesh.seed = d.mesh.seed;
  s.solver = d.solver;
  s.outputs = d.outputs;
  s.material.stabilization = d.material.stabilization;
  s.material.model = d.material.model;
  return s == d;
}

nlohmann::json opt_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }
std::string opt_csv(const std::optional<double>& v) {
  if (!v) return "";
  std::ostringstream s;
  s << std::setprecision(10) << *v;
  return s.str();
}

/// Solves the scene on N x N squares, reporting each solve; remembers whether every solve
/// converged.
struct SquaresSolver {
  const Scene& scene;
  const std::function<void(const StudySolveInfo&)>& solved;
  bool all_converged = true;

  SceneSolve operator()(int n) {
    Scene s = scene;
    s.mesh.n = n;
    s.mesh.ny.reset();  // N x N squares
    const auto t = Clock::now();
    SceneSolve r = solve_scene(s);
    all_converged = all_converged && r.solution.converged();
    if (solved)
      solved({n, r.built->mesh.num_vertices(), to_string(r.solution.status), r.solution.iterations(), since(t)});
    return r;
  }
};

/// One row per coarse size: the energy error of its solution, prolonged to the reference mesh,
/// relative to the reference's norm `ref_norm`, and the rate against the previous size. Each
/// coarse solve is dropped once measured.
std::vector<StudyRow> measure(SquaresSolver& solve, const std::vector<int>& ns, int ref_n, const SceneSolve& ref,
                              double ref_norm, bool references) {
  const Mesh& ref_mesh = ref.built->mesh;
  const MaterialTable& materials = ref.built->problem.elasticity.materials;
  const Eigen::VectorXd& u_ref = ref.solution.u;
  const auto& domain = solve.scene.mesh.domain;
  std::vector<StudyRow> rows;
  for (int n : ns) {
    const auto t = Clock::now();
    const SceneSolve c = solve(n);
    const Eigen::VectorXd diff = u_ref - prolong_squares(c.solution.u, n, ref_n);
    StudyRow row;
    row.n = n;
    row.h = std::max(domain[1] - domain[0], domain[3] - domain[2]) / n;
    const double error = std::sqrt(q1_energy(ref_mesh, materials, diff) / 2.0);
    row.error = error / ref_norm;
    if (c.estimate && std::isfinite(c.estimate->relative)) {
      row.estimate = c.estimate->relative;
      if (error > 0.0) row.effectivity = c.estimate->energy / error;
    }
    row.converged = c.solution.converged();
    row.iterations = c.solution.iterations();
    row.seconds = since(t);
    if (!rows.empty())
      row.rate = std::log(rows.back().error / row.error) / std::log(static_cast<double>(n) / rows.back().n);
    if (references) row.paper = paper_value(n), row.independent = independent_value(n);
    rows.push_back(row);
  }
  return rows;
}

void write_study_csv(const fs::path& path, const std::vector<StudyRow>& rows) {
  write_atomically(path, [&](std::ostream& os) {
    os << "h,N,error,rate,paper,independent,estimate,effectivity\n" << std::setprecision(10);
    for (const auto& r : rows)
      os << r.h << "," << r.n << "," << r.error << "," << opt_csv(r.rate) << "," << opt_csv(r.paper) << ","
         << opt_csv(r.independent) << "," << opt_csv(r.estimate) << "," << opt_csv(r.effectivity) << "\n";
  });
}

}  // namespace

std::string study_note() { return kNote; }

Figure study_figure(const std::vector<StudyPoint>& rows, bool with_references, int ref) {
  Figure f;
  f.png = "study.png";
  f.width = 900;
  f.height = 650;
  f.data.push_back({"study.dat", [rows](std::ostream& d) {
                      d << std::setprecision(12);
                      for (const auto& r : rows) {
                        d << r.h << " " << 100.0 * r.error;
                        for (const auto& v : {r.paper, r.independent}) {
                          if (v) d << " " << 100.0 * *v;
                          else d << " NaN";
                        }
                        d << "\n";
                      }
                    }});
  std::ostringstream g;
  g << std::setprecision(12) << "set logscale xy\nset grid\nset key bottom right\n"
    << "set title 'relative energy error against the solution on " << ref << " x " << ref << " squares'\n"
    << "set xlabel 'mesh size h (scene units)'\nset ylabel 'relative error in the energy norm (%)'\n"
    << "set datafile missing 'NaN'\n";
  const double slope = !rows.empty() && rows.front().h > 0.0 ? 100.0 * rows.front().error / rows.front().h : 0.0;
  g << "plot 'study.dat' using 1:2 with linespoints pt 7 lw 2 title 'hemivem'";
  if (slope > 0.0 && std::isfinite(slope)) g << ", " << slope << " * x with lines dt 2 lw 1.5 lc rgb '#555555' title 'O(h) reference slope'";
  if (with_references)
    g << ", 'study.dat' using 1:3 with linespoints pt 5 lw 1 title 'paper (Feng, Han, Huang 2021, Table 1)'"
      << ", 'study.dat' using 1:4 with points pt 6 ps 2 lw 1.5 title 'independent implementation of the paper''s section 2'";
  f.script = g.str();
  return f;
}

std::vector<int> study_sizes(const Scene& scene, const StudyOptions& o) {
  if (!scene.mesh.file.empty() || scene.mesh.generator != "squares")
    throw InputError("study needs nested square meshes (mesh.generator = squares)", scene.where("mesh.generator"));
  if (o.n.empty()) throw InputError("no N given", o.n_key);
  if (o.ref < 1) throw InputError("the reference N must be positive", o.ref_key);
  std::vector<int> ns = o.n;
  std::sort(ns.begin(), ns.end());
  ns.erase(std::unique(ns.begin(), ns.end()), ns.end());
  for (int n : ns) {
    if (n < 1) throw InputError("N = " + std::to_string(n) + " is not positive", o.n_key);
    if (n >= o.ref || o.ref % n != 0)
      throw InputError("N = " + std::to_string(n) + " does not divide the reference N = " + std::to_string(o.ref) +
                           " (study needs nested square meshes, coarser than the reference)",
                       o.n_key);
  }
  return ns;
}

StudyResult run_study(const Scene& scene, const StudyOptions& o) {
  const std::vector<int> ns = study_sizes(scene, o);
  StudyResult r;
  r.ref = o.ref;
  r.references = is_example_41(scene);
  SquaresSolver solve{scene, o.solved};
  // The reference first; its mesh and field stay.
  const SceneSolve ref = solve(o.ref);
  r.ref_norm = std::sqrt(q1_energy(ref.built->mesh, ref.built->problem.elasticity.materials, ref.solution.u) / 2.0);
  if (!(r.ref_norm > 0)) throw InputError("the reference solution is zero: there is no relative error to measure");
  r.ref_converged = ref.solution.converged();
  r.ref_iterations = ref.solution.iterations();
  r.rows = measure(solve, ns, o.ref, ref, r.ref_norm, r.references);
  r.converged = solve.all_converged;
  return r;
}

nlohmann::json study_json(const Scene& scene, const StudyOptions& o, const StudyResult& result) {
  nlohmann::json j;
  j["schema"] = "hemivem-study/2";
  j["scene"] = scene.title;
  j["source"] = scene.source;
  j["norm"] = "||v||_E = (1/sqrt 2) (sigma(v), eps(v))^(1/2), exact for the bilinear difference on the reference mesh";
  j["reference"] = {{"n", result.ref},
                    {"energy_norm", result.ref_norm},
                    {"converged", result.ref_converged},
                    {"iterations", result.ref_iterations}};
  j["plane_model"] = to_string(scene.material.model);
  j["stabilization"] = to_string(scene.material.stabilization);
  j["overrides"] = o.overrides;
  j["converged"] = result.converged;
  j["rows"] = nlohmann::json::array();
  for (const auto& r : result.rows)
    j["rows"].push_back({{"n", r.n},
                         {"h", r.h},
                         {"error", r.error},
                         {"rate", opt_json(r.rate)},
                         {"paper", opt_json(r.paper)},
                         {"independent", opt_json(r.independent)},
                         {"estimate", opt_json(r.estimate)},
                         {"effectivity", opt_json(r.effectivity)},
                         {"converged", r.converged},
                         {"iterations", r.iterations},
                         {"seconds", r.seconds}});
  j["estimate"] = "the solve's a posteriori estimate eta of ||u - u_h||_E relative to ||u_h||_E (docs/error-estimate.md)";
  j["effectivity"] = "eta / ||u_ref - P u_h||_E: the estimate over the error this study measures, in the same norm";
  if (result.references) j["note"] = kNote;
  return j;
}

StudyFiles write_study(const fs::path& dir, const Scene& scene, const StudyOptions& o, const StudyResult& result) {
  StudyFiles files;
  nlohmann::json& j = files.json;
  j = study_json(scene, o, result);
  files.written = {"study.csv", "study.json"};
  std::vector<StudyPoint> points;
  for (const auto& r : result.rows) points.push_back({r.h, r.error, r.paper, r.independent});
  std::vector<std::string> owned{"study.csv", "study.json"};
  for (const auto& format : figure_formats()) owned.push_back("study." + format);
  OutputTransaction tx(dir, owned);  // the folder changes at once
  tx.stage([&](const fs::path& staging) {
    write_study_csv(staging / "study.csv", result.rows);
    const Figure figure = study_figure(points, result.references, result.ref);
    files.skipped = draw_figures(staging, {figure}, scene.figure_formats).front();
    if (files.skipped.empty())
      for (const auto& file : figure_files(figure, scene.figure_formats)) files.written.push_back(file);
    else
      files.warnings = figure_warnings({{figure.png, files.skipped}});
    j["files"] = files.written;
    j["warnings"] = files.warnings;
    write_atomically(staging / "study.json", [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  });
  (void)tx.commit();
  return files;
}

}  // namespace hemivem::app
