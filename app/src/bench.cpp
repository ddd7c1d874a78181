#include <hemivem/app/bench.hpp>

#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/refine.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/support/output_folder.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <utility>

#include <hemivem/app/adapt.hpp>
#include <hemivem/app/figures.hpp>
#include <hemivem/app/format.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>

#include "scene_setup.hpp"

namespace hemivem::app {

namespace fs = std::filesystem;

double bench_stage(const PairRun& r, const std::string& name) {
  if (name == "mesh") return r.mesh_seconds;
  if (name == "total") return r.seconds;
  const auto it = r.timings.find(name);
  return it == r.timings.end() ? 0.0 : it->second;
}

std::string gridded_generator(const Scene& base) { return base.dimension() == 3 ? "cubes" : "squares or triangles"; }

bool measures_errors(const Scene& base) {
  if (!base.mesh.file.empty()) return false;
  const std::string& g = base.mesh.generator;
  return base.dimension() == 3 ? g == "cubes" : g == "squares" || g == "triangles";
}

namespace {

const std::vector<std::string>& file_stage_names() {
  // posing and full_space: a full-space pair's stages (0 for a condensed pair, whose condensation,
  // minimize and back_substitution are 0 on the full-space route)
  static const std::vector<std::string> names{"mesh",     "assembly",          "linear_solve", "condensation",
                                              "minimize", "back_substitution", "posing",       "full_space",
                                              "total"};
  return names;
}

}  // namespace

Eigen::VectorXd interpolate_squares(const Mesh& mesh, const Eigen::VectorXd& u, int n,
                                    const std::array<double, 4>& domain, const std::vector<Vec2>& points) {
  const double x0 = domain[0], y0 = domain[2];
  const double hx = (domain[1] - domain[0]) / n, hy = (domain[3] - domain[2]) / n;
  const int side = n + 1;
  if (mesh.num_vertices() != side * side || u.size() != 2 * mesh.num_vertices())
    throw InputError("not a squares mesh with n = " + std::to_string(n), "bench");
  std::vector<int> grid(static_cast<std::size_t>(side * side), -1);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double fi = (mesh.vertex(v).x() - x0) / hx, fj = (mesh.vertex(v).y() - y0) / hy;
    const long i = std::lround(fi), j = std::lround(fj);
    if (std::abs(fi - i) > 1e-6 || std::abs(fj - j) > 1e-6 || i < 0 || j < 0 || i > n || j > n)
      throw InputError("vertex " + std::to_string(v) + " is not on the squares grid", "bench");
    grid[static_cast<std::size_t>(j * side + i)] = v;
  }
  if (std::count(grid.begin(), grid.end(), -1) != 0)
    throw InputError("the squares grid has a missing vertex", "bench");
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

Eigen::VectorXd interpolate_cubes(const Mesh3D& mesh, const Eigen::VectorXd& u, const GridSize3& n,
                                  const std::array<double, 6>& box, const std::vector<Vec3>& points) {
  const int cells[3] = {n.nx, n.ny, n.nz};
  double low[3], h[3];
  for (int a = 0; a < 3; ++a) {
    low[a] = box[static_cast<std::size_t>(2 * a)];
    h[a] = (box[static_cast<std::size_t>(2 * a + 1)] - low[a]) / cells[a];
  }
  const long sx = n.nx + 1, sy = n.ny + 1, sz = n.nz + 1;
  if (mesh.num_vertices() != sx * sy * sz || u.size() != 3 * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("not a cubes mesh with n = " + n.text(), "bench");
  std::vector<int> grid(static_cast<std::size_t>(sx * sy * sz), -1);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    long index[3];
    for (int a = 0; a < 3; ++a) {
      const double f = (mesh.vertex(v)(a) - low[a]) / h[a];
      index[a] = std::lround(f);
      if (std::abs(f - static_cast<double>(index[a])) > 1e-6 || index[a] < 0 || index[a] > cells[a])
        throw InputError("vertex " + std::to_string(v) + " is not on the cubes grid", "bench");
    }
    grid[static_cast<std::size_t>((index[2] * sy + index[1]) * sx + index[0])] = v;
  }
  if (std::count(grid.begin(), grid.end(), -1) != 0) throw InputError("the cubes grid has a missing vertex", "bench");

  Eigen::VectorXd r(3 * static_cast<Eigen::Index>(points.size()));
  for (std::size_t k = 0; k < points.size(); ++k) {
    int cell[3];
    double t[3];
    for (int a = 0; a < 3; ++a) {
      const double f = (points[k](a) - low[a]) / h[a];
      cell[a] = std::clamp(static_cast<int>(std::floor(f)), 0, cells[a] - 1);
      t[a] = f - cell[a];
    }
    double value[3] = {0.0, 0.0, 0.0};
    for (int corner = 0; corner < 8; ++corner) {  // corner = cx + 2 cy + 4 cz
      const int c[3] = {corner & 1, corner >> 1 & 1, corner >> 2 & 1};
      double w = 1.0;
      for (int a = 0; a < 3; ++a) w *= c[a] ? t[a] : 1.0 - t[a];
      const int v = grid[static_cast<std::size_t>(((cell[2] + c[2]) * sy + cell[1] + c[1]) * sx + cell[0] + c[0])];
      for (int a = 0; a < 3; ++a) value[a] += w * u(3 * v + a);
    }
    for (int a = 0; a < 3; ++a) r(3 * static_cast<Eigen::Index>(k) + a) = value[a];
  }
  return r;
}

namespace {

/// The triangles of a mesh in buckets of a uniform grid over its bounding box (each triangle in
/// every bucket its bounding box meets), to find the triangle that holds a point.
struct TriangleBuckets {
  Rectangle box;
  int m = 1;  ///< buckets per side
  std::vector<std::vector<int>> cells;

  explicit TriangleBuckets(const Mesh& mesh) : box(mesh.bounding_box()) {
    m = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(mesh.num_elements()))));
    cells.resize(static_cast<std::size_t>(m * m));
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const auto v = mesh.element(e);
      const double inf = std::numeric_limits<double>::infinity();
      double lo[2] = {inf, inf}, hi[2] = {-inf, -inf};
      for (int k : v)
        for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], mesh.vertex(k)(a)), hi[a] = std::max(hi[a], mesh.vertex(k)(a));
      const auto [i0, j0] = bucket(Vec2(lo[0], lo[1]));
      const auto [i1, j1] = bucket(Vec2(hi[0], hi[1]));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) cells[static_cast<std::size_t>(j * m + i)].push_back(e);
    }
  }
  std::pair<int, int> bucket(const Vec2& p) const {
    const double fx = (p.x() - box.x0) / std::max(box.width(), 1e-300) * m;
    const double fy = (p.y() - box.y0) / std::max(box.height(), 1e-300) * m;
    return {std::clamp(static_cast<int>(std::floor(fx)), 0, m - 1), std::clamp(static_cast<int>(std::floor(fy)), 0, m - 1)};
  }
};

/// The barycentric coordinates of `p` in triangle `e` of `mesh`.
std::array<double, 3> barycentric(const Mesh& mesh, int e, const Vec2& p) {
  const auto v = mesh.element(e);
  const Vec2 a = mesh.vertex(v[0]), b = mesh.vertex(v[1]), c = mesh.vertex(v[2]);
  const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  const double l1 = ((p - a).x() * (c - a).y() - (p - a).y() * (c - a).x()) / det;
  const double l2 = ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x()) / det;
  return {1.0 - l1 - l2, l1, l2};
}

}  // namespace

Eigen::VectorXd interpolate_triangles(const Mesh& mesh, const Eigen::VectorXd& u, const std::vector<Vec2>& points) {
  if (u.size() != 2 * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("the displacement has " + std::to_string(u.size()) + " entries for " +
                         std::to_string(mesh.num_vertices()) + " vertices",
                     "bench");
  for (int e = 0; e < mesh.num_elements(); ++e)
    if (mesh.element_size(e) != 3)
      throw InputError("element " + std::to_string(e) + " has " + std::to_string(mesh.element_size(e)) +
                           " vertices: not a triangle mesh",
                       "bench");
  const TriangleBuckets buckets(mesh);
  Eigen::VectorXd r(2 * static_cast<Eigen::Index>(points.size()));
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto [i, j] = buckets.bucket(points[k]);
    int best = -1;
    std::array<double, 3> w{};
    double inside = -std::numeric_limits<double>::infinity();  // the smallest barycentric coordinate of the best triangle
    for (int e : buckets.cells[static_cast<std::size_t>(j * buckets.m + i)]) {
      const auto l = barycentric(mesh, e, points[k]);
      const double least = std::min({l[0], l[1], l[2]});
      if (least > inside) inside = least, best = e, w = l;
    }
    if (best < 0 || inside < -1e-8)
      throw InputError("the point (" + std::to_string(points[k].x()) + ", " + std::to_string(points[k].y()) +
                           ") is outside the triangle mesh",
                       "bench");
    const auto v = mesh.element(best);
    for (int c = 0; c < 2; ++c)
      r(2 * static_cast<Eigen::Index>(k) + c) = w[0] * u(2 * v[0] + c) + w[1] * u(2 * v[1] + c) + w[2] * u(2 * v[2] + c);
  }
  return r;
}

std::vector<int> bench_default_sizes(int dimension) {
  return dimension == 3 ? std::vector<int>{4, 8, 16} : std::vector<int>{16, 32, 64, 128};
}
int bench_default_ref(int dimension) { return dimension == 3 ? 32 : 256; }
int bench_default_levels(int dimension) { return dimension == 3 ? 2 : 3; }

namespace {

// Draws `f` into `dir` in `formats`: empty when drawn, else why not, which is also added to
// `failed` (the figure's name and the reason: a warning).
std::string draw_plot(const fs::path& dir, const Figure& f, const std::vector<std::string>& formats,
                      std::vector<std::pair<std::string, std::string>>& failed) {
  std::string reason = draw_figures(dir, {f}, formats).front();
  if (!reason.empty()) failed.emplace_back(f.png, reason);
  return reason;
}

// The work-precision figure: one series per pair, log error (x) against log total time (y).
// Empty on success, else why it was skipped.
std::string bench_plot(const fs::path& dir, const std::vector<Pair>& pairs, const std::vector<BenchRow>& rows,
                       const std::vector<std::string>& formats, std::vector<std::pair<std::string, std::string>>& failed) {
  std::vector<BenchSeries> series;
  for (const Pair& pair : pairs) {
    BenchSeries s{pair.linear, pair.minimizer, {}};
    for (const auto& r : rows)
      if (r.run.pair.label() == pair.label() && std::isfinite(r.error) && r.error > 0.0 && r.run.seconds > 0.0)
        s.points.push_back({r.error, r.run.seconds});
    series.push_back(std::move(s));
  }
  Figure f;
  f.script = bench_plot_script(series);
  if (f.script.empty()) return "no finite positive error to plot";
  f.png = "bench.png";
  f.width = 1100;
  f.height = 750;
  return draw_plot(dir, f, formats, failed);
}

}  // namespace

std::string bench_plot_script(const std::vector<BenchSeries>& series) {
  std::ostringstream script;
  script << std::setprecision(17);
  std::vector<std::string> linear = available_factorizations();  // then the full-space route's engines
  for (const auto& k : available_krylov_solvers()) linear.push_back(k);
  const auto minimizers = available_minimizers();
  auto index = [](const std::vector<std::string>& names, const std::string& name) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  // the series grouped by linear engine, in the order the engines first appear
  std::vector<std::string> engines;
  for (const auto& s : series)
    if (!s.points.empty() && std::find(engines.begin(), engines.end(), s.linear) == engines.end())
      engines.push_back(s.linear);
  if (engines.empty()) return {};
  std::vector<std::string> plots;
  for (const std::string& engine : engines) {
    if (!plots.empty()) plots.push_back("keyentry title ' '");  // a blank line between the groups
    plots.push_back("keyentry title " +
                    gnuplot_quote("linear engine " + engine + (is_krylov_solver(engine) ? " (full-space route)" : "")));
    for (std::size_t p = 0; p < series.size(); ++p) {
      const BenchSeries& s = series[p];
      if (s.linear != engine || s.points.empty()) continue;
      script << "$d" << p << " << EOD\n";
      for (const auto& [error, seconds] : s.points) script << error << ' ' << seconds << '\n';
      script << "EOD\n";
      // colour by minimizer, dash and point type by linear engine
      const std::size_t li = index(linear, s.linear), mi = index(minimizers, s.minimizer);
      plots.push_back("$d" + std::to_string(p) + " using 1:2 with linespoints lw 2 ps 1.3 lc " + std::to_string(mi + 1) +
                      " dt " + std::to_string(li + 1) + " pt " + std::to_string(2 * li + 5) + " title " +
                      gnuplot_quote("  " + s.minimizer));
    }
  }
  script << "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\n"
         << "set xlabel 'relative error: max|I_h u_h - u_{ref}| / max|u_{ref}| (dimensionless)'\n"
         << "set ylabel 'wall time, whole solve (s)'\n"
         << "set title 'work against precision: every pair of engines on every mesh size'\nset grid\n"
         << "set key outside right top Left reverse noenhanced\n"
         << "plot ";
  for (std::size_t i = 0; i < plots.size(); ++i) script << (i ? ", \\\n     " : "") << plots[i];
  script << "\n";
  return script.str();
}

std::optional<double> aitken_reference(double phi0, double phi1, double phi2) {
  const double d1 = phi0 - phi1, d2 = phi1 - phi2;
  if (!std::isfinite(d1) || !std::isfinite(d2) || d1 == 0.0) return std::nullopt;
  const double q = d2 / d1;
  if (!(q > 0.0 && q < 1.0)) return std::nullopt;
  const double ref = phi2 - d2 * d2 / (d1 - d2);
  if (!std::isfinite(ref)) return std::nullopt;
  return ref;
}

namespace {

// a plane or three-dimensional solve (app::SceneSolve, app::SceneSolve3D)
template <class Solve>
RefinementPoint uniform_point(const Solve& s, int level) {
  RefinementPoint p;
  p.kind = "uniform";
  p.index = level;
  p.unknowns = s.solution.unknowns;
  p.seconds = s.total_seconds();
  if (s.estimate) p.estimate = s.estimate->relative, p.norm = s.estimate->norm;
  p.potential_energy = s.solution.energy;
  p.status = to_string(s.solution.status);
  p.converged = s.solution.converged();
  return p;
}

RefinementPoint adaptive_point(const app::AdaptStep& step) {
  RefinementPoint p;
  p.kind = "adaptive";
  p.index = step.step;
  p.unknowns = step.unknowns;
  p.seconds = step.elapsed;
  p.estimate = step.estimate;
  if (std::isfinite(step.estimate) && step.estimate > 0.0) p.norm = step.estimate_energy / step.estimate;
  p.potential_energy = step.potential_energy;
  p.status = step.status;
  p.converged = step.status == to_string(MinimizerStatus::converged);
  return p;
}

void measure_true_errors(Refinement& r, const BenchOptions& o);

// The adaptive run of a refinement study, of a plane or a solid scene: from the scene's mesh to
// the finest uniform level's relative estimate, within its unknowns (Doerfler fraction 0.5).
template <int dim>
void run_adaptive(const Scene& base, Refinement& r, const std::function<void(const RefinementPoint&)>& progress) {
  const RefinementPoint& finest = r.uniform.back();
  if (!(std::isfinite(finest.estimate) && finest.estimate > 0.0 && finest.estimate < 1.0)) {
    r.stopped = "not_run";
    r.reason = "the finest uniform level has no relative estimate in (0, 1) to aim at";
    return;
  }
  SceneAdapt adapt;
  adapt.target = finest.estimate;
  adapt.fraction = 0.5;
  adapt.max_unknowns = finest.unknowns;
  adapt.max_steps = 50;
  std::conditional_t<dim == 2, app::SceneSolveOptions, app::SceneSolve3DOptions> options;
  const auto a = app::solve_adaptively(base, adapt, std::move(options), [&](const app::AdaptStep& step) {
    if (progress) progress(adaptive_point(step));
  });
  for (const app::AdaptStep& step : a.steps) r.adaptive.push_back(adaptive_point(step));
  r.stopped = app::to_string(a.stopped);
  r.reason = a.reason;
}

// Every uniform level of the refinement study fits in memory, checked once the first level's
// mesh is known and before any level is refined: uniform refinement gives a mesh of V + E + F
// vertices (the vertices, a midpoint per edge, a centre per element, all quadrilaterals), then
// four times as many per further level. InputError at `key` naming the first level that does
// not fit.
void require_level_memory(const Mesh& first, int levels, const std::string& key) {
  double vertices = first.num_vertices();
  for (int level = 1; level <= levels; ++level) {
    vertices = level == 1 ? vertices + first.num_edges() + first.num_elements() : 4.0 * vertices;
    require_memory(estimate_memory(vertices, 4.0).solve_bytes,
                   "refinement level " + std::to_string(level) + " (about " + sci(vertices) + " vertices)",
                   key);
  }
}

// The refinement study: the scene with its own engines on its own mesh refined uniformly
// o.levels times, then adaptively to the finest level's estimate, and the true errors against a
// reference energy (given, or Aitken's extrapolation of the last three uniform levels).
Refinement run_refinement(const Scene& base, const BenchOptions& o) {
  const auto& progress = o.progress.refinement;
  Refinement r;
  std::optional<Mesh> mesh;  // the previous level's mesh
  const bool path = scene_is_path(base);  // each level solved along the path, its last step measured
  r.levels = *o.levels;
  for (int level = 0; level <= *o.levels; ++level) {
    app::SceneSolveOptions so;
    if (mesh) {
      so.mesh = refine_uniformly(*mesh).mesh;
      so.apply_region_boxes = false;
      so.mesh_description = "the scene's mesh refined uniformly " + std::to_string(level) + " time" + (level > 1 ? "s" : "");
    }
    app::SceneSolve s = path ? app::solve_scene_path(base, std::move(so)) : app::solve_scene(base, std::move(so));
    if (level == 0) {
      r.engines = s.linear + " + " + s.minimizer;
      require_level_memory(s.built->mesh, *o.levels, o.keys.levels);
    }
    r.uniform.push_back(uniform_point(s, level));
    r.all_converged &= r.uniform.back().converged;
    if (progress) progress(r.uniform.back());
    mesh = std::move(s.built->mesh);  // s is done with
  }

  if (path) {
    r.stopped = "not_run";
    r.reason = "adaptive refinement solves one static problem and the scene is a loading path: the uniform levels "
               "are measured at the path's last step";
  } else {
    run_adaptive<2>(base, r, progress);
  }
  measure_true_errors(r, o);
  return r;
}

/// The uniform levels of a three-dimensional refinement study of a generated mesh: the scene
/// (level 0), then the scene with its generator's cell counts times 2^level (Voronoi: seeds per
/// axis), each level's memory checked. InputError naming `key` for a level beyond the
/// generators' 1000 cells per axis or the memory available.
std::vector<Scene> refinement_levels_3d(const Scene& base, int levels, const std::string& key) {
  std::vector<Scene> l;
  const GridSize3 cells = base.mesh.cells3();
  for (int level = 0; level <= levels; ++level) {
    const std::int64_t factor = std::int64_t{1} << level;
    const std::int64_t n[3] = {cells.nx * factor, cells.ny * factor, cells.nz * factor};
    if (*std::max_element(n, n + 3) > 1000)
      throw InputError("refinement level " + std::to_string(level) + " needs " + std::to_string(n[0]) + " x " +
                           std::to_string(n[1]) + " x " + std::to_string(n[2]) +
                           " cells (the scene's times 2^" + std::to_string(level) +
                           "); a three-dimensional generator takes at most 1000 per axis",
                       key);
    const GridSize3 size(static_cast<int>(n[0]), static_cast<int>(n[1]), static_cast<int>(n[2]));
    require_memory(estimate_memory_3d(base.mesh.generator, n[0], n[1], n[2]).solve_bytes,
                   "refinement level " + std::to_string(level) + ": " + base.mesh.generator + " n = " + size.text(),
                   key);
    Scene s = base;
    if (level > 0)
      apply_override(s, "mesh.n=[" + std::to_string(n[0]) + ", " + std::to_string(n[1]) + ", " +
                            std::to_string(n[2]) + "]");
    l.push_back(std::move(s));
  }
  return l;
}

// The refinement study of a three-dimensional scene: its levels (refinement_levels_3d) solved
// with the scene's own engines (solve_scene_3d), the adaptive run from the first level's mesh,
// and the true errors, as in 2D.
Refinement run_refinement_3d(const std::vector<Scene>& levels, const BenchOptions& o) {
  const auto& progress = o.progress.refinement;
  Refinement r;
  r.method = "cells_doubled";
  r.levels = *o.levels;
  for (std::size_t level = 0; level < levels.size(); ++level) {
    const app::SceneSolve3D s = app::solve_scene_3d(levels[level]);
    if (level == 0) r.engines = s.linear + " + " + s.minimizer;
    r.uniform.push_back(uniform_point(s, static_cast<int>(level)));
    r.all_converged &= r.uniform.back().converged;
    if (progress) progress(r.uniform.back());
  }
  if (scene_is_path(levels.front())) {
    r.stopped = "not_run";
    r.reason = "adaptive refinement solves one static problem and the scene is a loading path: the uniform levels "
               "are measured at the path's last step";
  } else {
    run_adaptive<3>(levels.front(), r, progress);
  }
  measure_true_errors(r, o);
  return r;
}

// The reference energy (given, or Aitken's extrapolation of the last three uniform levels) and
// every point's true error and effectivity against it.
void measure_true_errors(Refinement& r, const BenchOptions& o) {
  if (o.reference_energy) {
    r.reference_energy = o.reference_energy;
    r.reference = "given by " + o.keys.reference_energy;
  } else if (r.uniform.size() >= 3) {
    const std::size_t k = r.uniform.size() - 3;
    const double e0 = r.uniform[k].potential_energy, e1 = r.uniform[k + 1].potential_energy,
                 e2 = r.uniform[k + 2].potential_energy;
    r.reference_energy = aitken_reference(e0, e1, e2);
    std::ostringstream s;
    s << std::setprecision(10);
    if (r.reference_energy)
      s << "Aitken's delta-squared extrapolation of the potential energies of uniform levels " << k << ", " << k + 1
        << ", " << k + 2 << " (" << e0 << ", " << e1 << ", " << e2 << ")";
    else
      s << "none: the potential energies of uniform levels " << k << ", " << k + 1 << ", " << k + 2 << " (" << e0
        << ", " << e1 << ", " << e2 << ") do not decrease geometrically, so Aitken's extrapolation is not defined";
    r.reference = s.str();
  } else {
    r.reference = "none: Aitken's extrapolation needs three uniform levels (" + o.keys.levels + " 2 or more)";
  }
  if (r.reference_energy)
    for (auto* list : {&r.uniform, &r.adaptive})
      for (RefinementPoint& p : *list) {
        if (!(std::isfinite(p.potential_energy) && std::isfinite(p.norm) && p.norm > 0.0)) continue;
        // Phi_h(u_h) >= Phi(u) for a conforming minimization: a point below the reference says
        // the reference is too high, and has no error (null, not 0) but its energy difference
        p.energy_difference = p.potential_energy - *r.reference_energy;
        if (p.energy_difference < 0.0) {
          ++r.below_reference;
          continue;
        }
        p.error = std::sqrt(p.energy_difference) / p.norm;
        if (p.error > 0.0 && std::isfinite(p.estimate)) p.effectivity = p.estimate / p.error;
      }
}

nlohmann::json refinement_point_json(const RefinementPoint& p) {
  return {{p.kind == "uniform" ? "level" : "step", p.index},
          {"unknowns", p.unknowns},
          {"seconds", p.seconds},
          {"estimate", number(p.estimate)},
          {"error", number(p.error)},
          {"effectivity", number(p.effectivity)},
          {"potential_energy", number(p.potential_energy)},
          {"energy_difference", number(p.energy_difference)},
          {"status", p.status}};
}

nlohmann::json refinement_json(const Refinement& r) {
  nlohmann::json j;
  j["engines"] = r.engines;
  j["levels"] = r.levels;
  j["uniform_method"] = r.method;
  j["reference_energy"] = r.reference_energy ? nlohmann::json(*r.reference_energy) : nlohmann::json(nullptr);
  j["reference"] = r.reference;
  j["below_reference"] = r.below_reference;
  j["error_definition"] =
      "sqrt(Phi_h(u_h) - Phi_ref) / ||u_h||_E, ||v||_E^2 = 1/2 a(v, v), null where Phi_h(u_h) < Phi_ref (the "
      "reference is then too high: energy_difference = Phi_h(u_h) - Phi_ref is negative); effectivity = estimate / "
      "error";
  j["uniform"] = nlohmann::json::array();
  for (const auto& p : r.uniform) j["uniform"].push_back(refinement_point_json(p));
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& p : r.adaptive) steps.push_back(refinement_point_json(p));
  j["adaptive"] = {{"stopped", r.stopped}, {"reason", r.reason}, {"steps", steps}};
  return j;
}

// bench-error.png: the estimates (and with a reference the true errors, dashed) against unknowns
// and run time. Empty on success, else why it was skipped.
std::string refinement_plot(const fs::path& dir, const Scene& base, const Refinement& r,
                            std::vector<std::pair<std::string, std::string>>& failed) {
  std::vector<app::ConvergenceSeries> series;
  auto add = [&](const std::vector<RefinementPoint>& points, const std::string& name, bool truth) {
    app::ConvergenceSeries s;
    s.name = name;
    s.dashed = truth;
    for (const auto& p : points) {
      s.unknowns.push_back(p.unknowns);
      s.seconds.push_back(p.seconds);
      s.error.push_back(truth ? p.error : p.estimate);
    }
    series.push_back(std::move(s));
  };
  add(r.uniform, "uniform (estimate)", false);
  add(r.adaptive, "adaptive (estimate)", false);
  if (r.reference_energy) {
    add(r.uniform, "uniform (true error)", true);
    add(r.adaptive, "adaptive (true error)", true);
  }
  bool any = false;
  for (const auto& s : series)
    for (double e : s.error) any |= std::isfinite(e) && e > 0.0;
  if (!any) return "no finite positive error to plot";
  return draw_plot(dir, app::convergence_figure(series, base.title + ": uniform and adaptive refinement", "bench-error.png",
                                                   base.dimension()),
                   base.figure_formats, failed);
}

/// `base` with mesh.n = n: n cells per side, as `--set mesh.n=n` gives (n x n x n in 3D).
Scene at_size(const Scene& base, int n) {
  Scene s = base;
  const std::string k = std::to_string(n);
  // [n, n, n] keeps a scene three-dimensional whose dimension only its mesh.n = [nx, ny, nz] gave
  apply_override(s, base.dimension() == 3 ? "mesh.n=[" + k + ", " + k + ", " + k + "]" : "mesh.n=" + k);
  return s;
}

// The reference: the finest mesh, the exact active-set method on a direct solver.
BenchReference run_reference(const Scene& base, const BenchOptions& o, bool gridded) {
  const BenchProgress& progress = o.progress;
  const auto linear = available_factorizations();
  BenchReference ref;
  ref.pair = Pair{std::find(linear.begin(), linear.end(), "cholmod") != linear.end() ? "cholmod" : "eigen", "ssn"};
  if (gridded) {
    if (progress.reference_started) progress.reference_started(ref.pair, *o.ref);
    PairRuns r = run_pairs(at_size(base, *o.ref), {ref.pair});
    ref.run = std::move(r.runs.front());
    if (ref.run.failed) throw NumericalError("the reference " + ref.pair.label() + " failed: " + ref.run.message);
    if (r.built3d) ref.points3d = r.built3d->mesh.vertices();
    else ref.points = r.built->mesh.vertices();
    ref.scale = max_abs(ref.run.u);
    if (ref.scale == 0.0) ref.scale = 1.0;
    if (progress.reference_done) progress.reference_done(ref.run);
  } else if (progress.not_gridded) {
    progress.not_gridded(gridded_generator(base));
  }
  return ref;
}

// Per size, the pairs share the mesh, the assembly and each linear engine's condensation
// (engine_pairs.hpp); the rows are listed pair by pair. `all_converged` is cleared when a run
// does not converge.
std::vector<BenchRow> run_sizes(const std::vector<Scene>& scenes, const std::vector<Pair>& pairs, const BenchOptions& o,
                                const BenchReference* ref, bool& all_converged) {
  std::vector<std::vector<BenchRow>> by_pair(pairs.size());
  for (std::size_t k = 0; k < o.n.size(); ++k) {
    PairRunOptions ro;
    if (o.progress.pair_done) ro.done = [&](const PairRun& r) { o.progress.pair_done(r, o.n[k]); };
    PairRuns shared = run_pairs(scenes[k], pairs, ro);
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      BenchRow row;
      row.n = o.n[k];
      row.run = std::move(shared.runs[p]);
      if (ref && !row.run.failed) {
        const Eigen::VectorXd fine =
            shared.built3d                             ? interpolate_cubes(shared.built3d->mesh, row.run.u, scenes[k].mesh.cells3(),
                                                                           scenes[k].mesh.box, ref->points3d)
            : scenes[k].mesh.generator == "triangles" ? interpolate_triangles(shared.built->mesh, row.run.u, ref->points)
                                                       : interpolate_squares(shared.built->mesh, row.run.u, o.n[k],
                                                                             scenes[k].mesh.domain, ref->points);
        row.error = max_abs(fine - ref->run.u) / ref->scale;
      }
      all_converged &= row.run.converged || row.run.refused;  // a route that refuses the scene is no failure
      by_pair[p].push_back(std::move(row));
    }
  }
  std::vector<BenchRow> rows;
  for (auto& list : by_pair)
    for (auto& row : list) rows.push_back(std::move(row));
  return rows;
}

void write_bench_csv(const fs::path& csv, const std::vector<BenchRow>& rows) {
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
      for (const auto& s : file_stage_names()) os << ',' << bench_stage(r.run, s);
      os << ',';
      if (std::isfinite(r.error)) os << r.error;
      os << '\n';
    }
  });
}

// The options with the defaults of the scene's dimension where a flag was not given; a scene
// whose mesh is read from a file is refused (it has no size to set).
BenchOptions bench_options_for(const BenchOptions& given, const Scene& base) {
  const bool solid = base.dimension() == 3;
  BenchOptions o = given;
  if (o.n.empty()) o.n = bench_default_sizes(base.dimension());
  if (!o.ref) o.ref = bench_default_ref(base.dimension());
  if (!o.levels) o.levels = bench_default_levels(base.dimension());
  // Every size is validated before any work; a mesh read from a file has no size to set.
  if (!base.mesh.file.empty())
    throw InputError("the scene reads its mesh from " + base.mesh.file.filename().string() +
                         ", and bench solves the scene at each mesh size by setting mesh.n: give a scene whose mesh "
                         "is made by a generator (mesh.generator" +
                         (solid ? ", e.g. cubes" : ", e.g. squares") + "), or time the file's mesh with hemivem check",
                     o.keys.n);
  return o;
}

// Every size fits in memory before any work, the reference included; in 3D every mesh is nested
// in the reference mesh (the error is the largest difference of two trilinear fields only when
// every mesh's vertices are vertices of the reference mesh).
void check_bench_sizes(const Scene& base, const std::vector<Scene>& scenes, const BenchOptions& o, bool gridded) {
  const bool solid = base.dimension() == 3;
  if (gridded && solid)
    for (int n : o.n)
      if (*o.ref % n != 0)
        throw InputError("a three-dimensional scene measures the error at the vertices of the reference mesh, "
                         "which must be nested in every mesh: " + o.keys.ref + " " + std::to_string(*o.ref) +
                             " is not a multiple of " + o.keys.n + " " + std::to_string(n),
                         o.keys.ref);
  auto require = [&](const Scene& s, const std::string& where) {
    if (s.mesh.file.empty()) detail::require_memory_of(s, where);
  };
  for (const Scene& s : scenes) require(s, o.keys.n);
  if (gridded) require(at_size(base, *o.ref), o.keys.ref);
}

}  // namespace

nlohmann::json bench_path_json(const Scene& base) {
  if (!scene_is_path(base)) return nullptr;
  const std::vector<double> t = base.path ? base.path->factors() : std::vector<double>{1.0};
  std::ostringstream last;
  last << std::setprecision(10) << t.back();
  return {{"steps", t.size()},
          {"t", t},
          {"measured", "the last step: every pair, the reference and every refinement level solve the whole path, and "
                       "the displacement, error and energy are those of its last step (t = " +
                           last.str() + "), the times those of the whole path"}};
}

nlohmann::json bench_json(const BenchResult& result) {
  const Scene& base = result.plan.base;
  const bool gridded = result.plan.gridded;
  const BenchReference& ref = result.reference;
  nlohmann::json j;
  j["schema"] = "hemivem-bench/6";
  j["version"] = HEMIVEM_VERSION;
  j["scene"] = base.title;
  j["source"] = base.source;
  j["dimension"] = base.dimension();
  j["mesh"] = base.mesh.file.empty() ? base.mesh.generator : base.mesh.file.string();
  j["tolerance"] = base.solver.tolerance;
  if (!gridded)
    j["error_definition"] = "not computed: the scene's mesh is not " + gridded_generator(base);
  else if (base.dimension() == 3)
    j["error_definition"] =
        "max over the reference vertices and the three components of |I_h u_h - u_ref| / max|u_ref|, I_h the "
        "trilinear interpolation of the cubes solution (exact prolongation: the reference mesh is nested in every "
        "mesh, --ref a multiple of every --n)";
  else if (base.mesh.generator == "triangles")
    j["error_definition"] =
        "max over the reference vertices and both components of |u_h - u_ref| / max|u_ref|, u_h evaluated at the "
        "reference vertices by linear interpolation on its triangle (on triangles the lowest-order virtual element "
        "space is the linear P1 space: the value of u_h itself; the meshes need not nest)";
  else
    j["error_definition"] =
        "max over the reference vertices and both components of |I_h u_h - u_ref| / max|u_ref|, "
        "I_h the bilinear interpolation of the squares solution (exact prolongation for nested meshes)";
  j["path"] = bench_path_json(base);
  if (gridded)
    j["reference"] = {{"n", *result.plan.options.ref},
                      {"linear", ref.pair.linear},
                      {"minimizer", ref.pair.minimizer},
                      {"status", ref.run.status},
                      {"converged", ref.run.converged},
                      {"vertices", ref.run.vertices},
                      {"seconds", ref.run.seconds},
                      {"max_abs_u", ref.scale}};
  else
    j["reference"] = nullptr;
  j["rows"] = nlohmann::json::array();
  for (const auto& r : result.rows) {
    nlohmann::json times;
    for (const auto& s : file_stage_names()) times[s] = bench_stage(r.run, s);
    j["rows"].push_back({{"linear", r.run.pair.linear},
                         {"minimizer", r.run.pair.minimizer},
                         {"route", r.run.pair.route()},
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
  j["refinement"] = refinement_json(result.refinement);
  return j;
}

void check_bench_options(const BenchOptions& given) {
  const BenchKeys& k = given.keys;
  for (int n : given.n)
    if (n < 1) throw InputError("mesh sizes must be >= 1, got " + std::to_string(n), k.n);
  if (given.ref && *given.ref < 1) throw InputError("must be >= 1", k.ref);
  if (given.levels && *given.levels < 1)
    throw InputError("must be >= 1 (uniform refinements of the scene's mesh), got " + std::to_string(*given.levels),
                     k.levels);
  if (given.reference_energy && !std::isfinite(*given.reference_energy))
    throw InputError("must be a finite number", k.reference_energy);
}

BenchPlan plan_bench(const Scene& scene, const BenchOptions& given) {
  check_bench_options(given);
  BenchPlan plan;
  plan.base = scene;
  plan.options = bench_options_for(given, scene);
  BenchOptions& o = plan.options;
  for (int n : o.n) plan.scenes.push_back(at_size(scene, n));
  plan.gridded = measures_errors(scene);
  if (!plan.gridded && given.ref)
    throw InputError("errors are measured against a reference solution on " + gridded_generator(scene) +
                         " meshes only, and the scene's mesh is " + scene.mesh.generator +
                         ": no reference is solved; drop " + o.keys.ref + ", or set mesh.generator to " +
                         (scene.dimension() == 3 ? std::string("cubes") : std::string("squares or triangles")),
                     o.keys.ref);
  check_bench_sizes(scene, plan.scenes, o, plan.gridded);
  if (scene.dimension() == 3) plan.levels = refinement_levels_3d(scene, *o.levels, o.keys.levels);
  if (o.pairs.empty()) o.pairs = available_pairs();
  return plan;
}

BenchResult run_bench(const BenchPlan& plan) {
  const BenchOptions& o = plan.options;
  BenchResult result;
  result.plan = plan;
  result.reference = run_reference(plan.base, o, plan.gridded);
  bool all_converged = !plan.gridded || result.reference.run.converged;
  result.rows = run_sizes(plan.scenes, o.pairs, o, plan.gridded ? &result.reference : nullptr, all_converged);
  result.refinement = plan.base.dimension() == 3 ? run_refinement_3d(plan.levels, o) : run_refinement(plan.base, o);
  result.converged = all_converged && result.refinement.all_converged;
  return result;
}

BenchResult run_bench(const Scene& scene, const BenchOptions& options) { return run_bench(plan_bench(scene, options)); }

BenchFiles write_bench(const fs::path& dir, const BenchResult& result) {
  BenchFiles files;
  nlohmann::json& j = files.json;
  j = bench_json(result);
  const std::vector<std::string>& formats = result.plan.base.figure_formats;
  std::vector<std::string> owned{"bench.csv", "bench.json"};
  for (const char* figure : {"bench", "bench-error"})  // in every format: an earlier run's goes
    for (const auto& format : figure_formats()) owned.push_back(std::string(figure) + "." + format);
  OutputTransaction tx(dir, owned);
  tx.stage([&](const fs::path& staging) {
    write_bench_csv(staging / "bench.csv", result.rows);
    std::vector<std::pair<std::string, std::string>> failed;
    Figure named;
    files.plot_skipped = bench_plot(staging, result.plan.options.pairs, result.rows, formats, failed);
    named.png = "bench.png";
    j["plot"] = files.plot_skipped.empty() ? nlohmann::json(figure_files(named, formats).front()) : nlohmann::json(nullptr);
    j["plot_files"] = files.plot_skipped.empty() ? figure_files(named, formats) : std::vector<std::string>();
    if (!files.plot_skipped.empty()) j["plot_skipped"] = files.plot_skipped;
    files.refinement_plot_skipped = refinement_plot(staging, result.plan.base, result.refinement, failed);
    named.png = "bench-error.png";
    j["refinement"]["plot"] = files.refinement_plot_skipped.empty() ? nlohmann::json(figure_files(named, formats).front())
                                                                    : nlohmann::json(nullptr);
    j["refinement"]["plot_files"] =
        files.refinement_plot_skipped.empty() ? figure_files(named, formats) : std::vector<std::string>();
    if (!files.refinement_plot_skipped.empty()) j["refinement"]["plot_skipped"] = files.refinement_plot_skipped;
    files.warnings = figure_warnings(failed);
    j["warnings"] = files.warnings;
    write_atomically(staging / "bench.json", [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  });
  (void)tx.commit();
  return files;
}

}  // namespace hemivem::app
