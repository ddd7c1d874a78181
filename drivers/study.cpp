#include "study.hpp"

#include <hemivem/vem/bilinear.hpp>
#include <hemivem/error.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/support/output_folder.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>
#include <unistd.h>

#include "commands.hpp"
#include "common.hpp"
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/figures.hpp>

namespace hemivem::cli {

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

struct Row {
  int n = 0;
  double h = 0.0;
  double error = 0.0;
  std::optional<double> rate, paper, independent;
  std::optional<double> estimate;     ///< the solve's relative error estimate eta / ||u_h||_E
  std::optional<double> effectivity;  ///< eta / ||u_ref - P u_h||_E
  bool converged = false;
  int iterations = 0;
  double seconds = 0.0;
};

std::string percent(const std::optional<double>& v, int precision = 2) {
  if (!v) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << 100.0 * *v << " %";
  return s.str();
}

std::string h_text(int n, const std::array<double, 4>& d) {
  if (d[0] == 0.0 && d[1] == 1.0 && d[2] == 0.0 && d[3] == 1.0) return "1/" + std::to_string(n);
  std::ostringstream s;
  s << std::setprecision(4) << std::max(d[1] - d[0], d[3] - d[2]) / n;
  return s.str();
}

nlohmann::json opt_json(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }
std::string opt_csv(const std::optional<double>& v) {
  if (!v) return "";
  std::ostringstream s;
  s << std::setprecision(10) << *v;
  return s.str();
}

}  // namespace

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

namespace {

/// The coarse sizes N of --n, sorted and distinct, each dividing the reference N.
std::vector<int> study_sizes(const StudyOptions& o) {
  if (o.n.empty()) throw InputError("no N given", "--n");
  if (o.ref < 1) throw InputError("the reference N must be positive", "--ref");
  std::vector<int> ns = o.n;
  std::sort(ns.begin(), ns.end());
  ns.erase(std::unique(ns.begin(), ns.end()), ns.end());
  for (int n : ns) {
    if (n < 1) throw InputError("N = " + std::to_string(n) + " is not positive", "--n");
    if (n >= o.ref || o.ref % n != 0)
      throw InputError("N = " + std::to_string(n) + " does not divide the reference N = " + std::to_string(o.ref) +
                           " (study needs nested square meshes, coarser than the reference)",
                       "--n");
  }
  return ns;
}

/// Solves the scene on N x N squares, reporting progress; remembers whether every solve
/// converged.
struct SquaresSolver {
  const Scene& scene;
  bool progress;
  std::ostream& err;
  bool all_converged = true;

  SceneSolve operator()(int n) {
    Scene s = scene;
    s.mesh.n = n;
    s.mesh.ny.reset();  // N x N squares
    const auto t = Clock::now();
    SceneSolve r = solve_scene(s);
    all_converged = all_converged && r.solution.converged();
    if (progress)
      err << "hemivem study: N = " << n << ": " << r.built->mesh.num_vertices() << " vertices, "
          << to_string(r.solution.status) << " (" << r.solution.iterations() << " iterations), "
          << std::fixed << std::setprecision(2) << since(t) << std::defaultfloat << " s\n";
    return r;
  }
};

/// One row per coarse size: the energy error of its solution, prolonged to the reference mesh,
/// relative to the reference's norm `ref_norm`, and the rate against the previous size. Each
/// coarse solve is dropped once measured.
std::vector<Row> measure(SquaresSolver& solve, const std::vector<int>& ns, int ref_n, const SceneSolve& ref,
                         double ref_norm, bool references) {
  const Mesh& ref_mesh = ref.built->mesh;
  const MaterialTable& materials = ref.built->problem.elasticity.materials;
  const Eigen::VectorXd& u_ref = ref.solution.u;
  const auto& domain = solve.scene.mesh.domain;
  std::vector<Row> rows;
  for (int n : ns) {
    const auto t = Clock::now();
    const SceneSolve c = solve(n);
    const Eigen::VectorXd diff = u_ref - prolong_squares(c.solution.u, n, ref_n);
    Row row;
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

/// study.json (schema hemivem-study/2).
nlohmann::json study_json(const Scene& scene, const StudyOptions& o, const SceneSolve& ref, double ref_norm,
                          bool all_converged, const std::vector<Row>& rows, bool references) {
  nlohmann::json j;
  j["schema"] = "hemivem-study/2";
  j["scene"] = scene.title;
  j["source"] = scene.source;
  j["norm"] = "||v||_E = (1/sqrt 2) (sigma(v), eps(v))^(1/2), exact for the bilinear difference on the reference mesh";
  j["reference"] = {{"n", o.ref},
                    {"energy_norm", ref_norm},
                    {"converged", ref.solution.converged()},
                    {"iterations", ref.solution.iterations()}};
  j["plane_model"] = to_string(scene.material.model);
  j["stabilization"] = to_string(scene.material.stabilization);
  j["overrides"] = o.set;
  j["converged"] = all_converged;
  j["rows"] = nlohmann::json::array();
  for (const auto& r : rows)
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
  if (references) j["note"] = kNote;
  return j;
}

void write_study_csv(const fs::path& path, const std::vector<Row>& rows) {
  write_atomically(path, [&](std::ostream& os) {
    os << "h,N,error,rate,paper,independent,estimate,effectivity\n" << std::setprecision(10);
    for (const auto& r : rows)
      os << r.h << "," << r.n << "," << r.error << "," << opt_csv(r.rate) << "," << opt_csv(r.paper) << ","
         << opt_csv(r.independent) << "," << opt_csv(r.estimate) << "," << opt_csv(r.effectivity) << "\n";
  });
}

void print_study(std::ostream& out, const Scene& scene, const StudyOptions& o, const std::vector<Row>& rows,
                 bool references, const std::vector<std::string>& written, const std::string& skipped) {
  out << "hemivem study: " << scene.title << " (" << scene.source << "), squares, reference N = " << o.ref << ", "
      << to_string(scene.material.model) << ", stabilization " << to_string(scene.material.stabilization) << "\n"
      << "  relative energy error ||u_ref - P u_h||_E / ||u_ref||_E (exact, bilinear, on the reference mesh);\n"
      << "  estimate eta / ||u_h||_E (a posteriori), effectivity eta / ||u_ref - P u_h||_E\n\n";
  out << std::right << std::setw(8) << "h" << std::setw(6) << "N" << std::setw(11) << "error" << std::setw(7) << "rate"
      << std::setw(11) << "paper" << std::setw(14) << "independent" << std::setw(11) << "estimate" << std::setw(13)
      << "effectivity" << "\n";
  for (const auto& r : rows) {
    std::ostringstream rate;
    if (r.rate) rate << std::fixed << std::setprecision(2) << *r.rate;
    else rate << "-";
    out << std::setw(8) << h_text(r.n, scene.mesh.domain) << std::setw(6) << r.n << std::setw(11) << percent(r.error)
        << std::setw(7) << rate.str() << std::setw(11) << percent(r.paper, r.n == 64 ? 3 : 2) << std::setw(14)
        << percent(r.independent) << std::setw(11) << percent(r.estimate) << std::setw(13)
        << (r.effectivity ? fixed(*r.effectivity, 2) : std::string("-")) << (r.converged ? "" : "  (not converged)") << "\n";
  }
  out << "\n";
  if (references) out << "  note: " << kNote << ".\n";
  out << "  wrote " << o.out << "/ (";
  for (std::size_t i = 0; i < written.size(); ++i) out << (i ? ", " : "") << written[i];
  out << ")\n";
  if (!skipped.empty()) out << "  skipped study.png: " << skipped << "\n";
}

}  // namespace

int run_study(const StudyOptions& o, std::ostream& out, std::ostream& err) {
  Scene scene = o.scene.empty() ? default_scene() : parse_scene(o.scene);
  apply_overrides(scene, o.set);
  if (!scene.mesh.file.empty() || scene.mesh.generator != "squares")
    throw InputError("study needs nested square meshes (mesh.generator = squares)", scene.where("mesh.generator"));
  const std::vector<int> ns = study_sizes(o);
  const bool references = is_example_41(scene);
  check_output_folder(o.out);
  SquaresSolver solve{scene, o.verbosity >= 1, err};

  // The reference first; its mesh and field stay.
  const SceneSolve ref = solve(o.ref);
  const double ref_norm =
      std::sqrt(q1_energy(ref.built->mesh, ref.built->problem.elasticity.materials, ref.solution.u) / 2.0);
  if (!(ref_norm > 0)) throw InputError("the reference solution is zero: there is no relative error to measure");
  const std::vector<Row> rows = measure(solve, ns, o.ref, ref, ref_norm, references);

  // Outputs.
  const nlohmann::json j = study_json(scene, o, ref, ref_norm, solve.all_converged, rows, references);
  std::vector<std::string> written{"study.csv", "study.json"};
  std::vector<StudyPoint> points;
  for (const auto& r : rows) points.push_back({r.h, r.error, r.paper, r.independent});
  std::string skipped;
  OutputTransaction tx(o.out, {"study.csv", "study.json", "study.png"});  // the folder changes at once
  tx.stage([&](const fs::path& staging) {
    write_study_csv(staging / "study.csv", rows);
    write_atomically(staging / "study.json", [&](std::ostream& os) { os << j.dump(2) << "\n"; });
    skipped = draw_figures(staging, {study_figure(points, references, o.ref)}).front();
  });
  if (skipped.empty()) written.emplace_back("study.png");
  (void)tx.commit();

  if (o.json)
    out << j.dump(2) << "\n";
  else if (o.verbosity >= 1)
    print_study(out, scene, o, rows, references, written, skipped);
  return solve.all_converged && ref.solution.converged() ? kSuccess : kNotConverged;
}

}  // namespace hemivem::cli
