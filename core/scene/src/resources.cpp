#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/support/names.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

namespace hemivem {

namespace {

constexpr double kBaseBytes = 24.0 * 1024 * 1024;

// The limit and where it came from.
struct Limit {
  double bytes = std::numeric_limits<double>::infinity();
  std::string source;
};

Limit memory_limit() {
  if (const char* env = std::getenv("HEMIVEM_MEMORY_LIMIT"); env && *env) {
    const std::string text(env);
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    std::string suffix = to_lower(text.substr(used));
    if (!suffix.empty() && suffix.back() == 'b') suffix.pop_back();
    if (suffix.size() == 2 && suffix.back() == 'i') suffix.pop_back();
    double scale = 1.0;
    if (suffix == "k") scale = 1024.0;
    else if (suffix == "m") scale = 1024.0 * 1024;
    else if (suffix == "g") scale = 1024.0 * 1024 * 1024;
    else if (suffix == "t") scale = 1024.0 * 1024 * 1024 * 1024;
    else if (!suffix.empty()) used = 0;
    if (used == 0 || !(value > 0.0) || !std::isfinite(value))
      throw InputError("expected a positive number of bytes with an optional suffix K, M, G or T, got '" + text + "'",
                       "HEMIVEM_MEMORY_LIMIT");
    return {value * scale, "HEMIVEM_MEMORY_LIMIT"};
  }
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0.0;
  std::string unit;
  while (meminfo >> key >> kib) {
    std::getline(meminfo, unit);
    if (key == "MemAvailable:") return {kib * 1024.0, "MemAvailable in /proc/meminfo"};
  }
  return {};
}

std::string sci(double v) {
  std::ostringstream s;
  s << std::setprecision(2) << std::scientific << v;
  return s.str();
}

}  // namespace

MemoryEstimate estimate_memory(double vertices, double vertices_per_element) {
  MemoryEstimate e;
  e.vertices = std::max(vertices, 1.0);
  // 1.1 times the largest measured peak of `hemivem solve` over the engines (eigen's): squares
  // N = 512, Voronoi N = 256 (docs/performance.md)
  const double c = vertices_per_element > 4.5 ? 468.0 : 258.0;
  e.solve_bytes = kBaseBytes + c * e.vertices * std::log2(std::max(e.vertices, 2.0));
  e.mesh_bytes = kBaseBytes + 400.0 * e.vertices;
  return e;
}

MemoryEstimate estimate_memory(const Mesh& mesh) {
  double corners = 0.0, squares = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const double m = mesh.element_size(e);
    corners += m;
    squares += m * m;
  }
  return estimate_memory(mesh.num_vertices(), mesh.num_elements(), corners, squares);
}

MemoryEstimate estimate_memory(double vertices, double elements, double corners, double corners_squared) {
  MemoryEstimate est = estimate_memory(vertices, elements > 0 ? corners / elements : 4.0);
  const double entries = 4.0 * corners_squared;  // each element's 2m x 2m stiffness matrix
  est.element_matrix_entries = entries;
  // 1.1 times the measured peak of eigen on one element of 1000 and of 2000 vertices: 64 and 60
  // bytes per entry of its matrix (the matrix, its products, the sparse assembly, the factor)
  est.solve_bytes = std::max(est.solve_bytes, kBaseBytes + 70.0 * entries);
  return est;
}

MemoryEstimate estimate_memory(std::string_view generator, std::int64_t n) { return estimate_memory(generator, n, n); }

MemoryEstimate estimate_memory(std::string_view generator, std::int64_t nx, std::int64_t ny) {
  if (nx < 1 || ny < 1)
    throw InputError("the number of cells per side n must be >= 1, got " +
                     (nx == ny ? std::to_string(nx) : "[" + std::to_string(nx) + ", " + std::to_string(ny) + "]"));
  const std::string g = to_lower(generator);
  const double x = static_cast<double>(nx), y = static_cast<double>(ny);
  if (g == "squares" || g == "distorted" || g == "polar") return estimate_memory((x + 1) * (y + 1), 4.0);
  if (g == "triangles") return estimate_memory((x + 1) * (y + 1), 3.0);
  if (g == "voronoi") return estimate_memory(2.0 * x * y + 2.0, 6.0);
  if (g == "nonconvex") return estimate_memory(3.0 * x * y + 1.0, 6.0);
  std::string names;
  for (const auto& name : mesh_generator_names()) names += (names.empty() ? "" : ", ") + name;
  throw InputError("unknown mesh generator '" + std::string(generator) + "' (expected one of: " + names + ")");
}

MemoryEstimate estimate_memory_3d(double vertices, double contact_nodes, double per_vertex) {
  MemoryEstimate e;
  e.vertices = std::max(vertices, 1.0);
  e.solve_bytes = kBaseBytes + per_vertex * std::pow(e.vertices, 4.0 / 3.0) + 48.0 * contact_nodes * contact_nodes;
  e.mesh_bytes = kBaseBytes + 1500.0 * e.vertices;
  return e;
}

MemoryEstimate estimate_memory_3d(std::string_view generator, std::int64_t nx, std::int64_t ny, std::int64_t nz) {
  if (nx < 1 || ny < 1 || nz < 1)
    throw InputError("the number of cells along each axis must be >= 1, got [" + std::to_string(nx) + ", " +
                     std::to_string(ny) + ", " + std::to_string(nz) + "]");
  const std::string g = to_lower(generator);
  const double x = static_cast<double>(nx), y = static_cast<double>(ny), z = static_cast<double>(nz);
  const double side = std::max({(x + 1) * (y + 1), (y + 1) * (z + 1), (x + 1) * (z + 1)});
  if (g == "cubes" || g == "tetrahedra") return estimate_memory_3d((x + 1) * (y + 1) * (z + 1), side);
  // a 3D Voronoi tessellation has about 6.8 vertices per cell
  if (g == "voronoi") return estimate_memory_3d(6.8 * x * y * z + 8.0, side, 3600.0);
  throw InputError("unknown 3D mesh generator '" + std::string(generator) + "' (expected one of: cubes, tetrahedra, voronoi)");
}

FullSpaceCost full_space_cost(int dimension, std::string_view generator, std::string_view engine) {
  // the peaks measured per engine (Example 4.1: squares N = 512, Voronoi N = 256; cubes n = 24
  // and 48, tetrahedra n = 24, Voronoi cells n = 12 and 16), less the process of a tiny mesh,
  // 20 % added (docs/full-space.md)
  const bool voronoi = to_lower(generator) == "voronoi";
  const std::string e = normalized_engine_name(engine);
  const int column = e == "petsc-hypre" ? 1 : (e == "eigen-cg" ? 2 : 0);  // petsc-gamg first
  static constexpr double kilobytes[2][2][3] = {
      {{2.9, 3.5, 2.9}, {3.5, 5.1, 4.9}},     // plane: polygons, Voronoi cells
      {{14.0, 23.0, 18.0}, {27.0, 41.0, 46.0}}};  // solid: cubes and tetrahedra, Voronoi cells
  FullSpaceCost cost;
  cost.base_bytes = e == "eigen-cg" ? kBaseBytes : 56.0 * 1024 * 1024;  // PETSc, MPI and hypre loaded
  cost.bytes_per_vertex = 1.0e3 * kilobytes[dimension == 3 ? 1 : 0][voronoi ? 1 : 0][column];
  return cost;
}

MemoryEstimate full_space_memory(const MemoryEstimate& condensed, const FullSpaceCost& cost) {
  MemoryEstimate e = condensed;
  e.solve_bytes = cost.base_bytes + cost.bytes_per_vertex * e.vertices;
  return e;
}

double available_memory() { return memory_limit().bytes; }

namespace {
// the scopes alive, the latest last (an object may end before a later one: each leaves alone)
std::vector<const MemoryOfProcesses*>& runs() {
  static std::vector<const MemoryOfProcesses*> alive;
  return alive;
}
const MemoryOfProcesses* current_run() { return runs().empty() ? nullptr : runs().back(); }
}  // namespace

MemoryOfProcesses::MemoryOfProcesses(int processes, bool whole_on_each, double base_bytes)
    : processes_(std::max(processes, 1)), whole_on_each_(whole_on_each), base_bytes_(base_bytes) {
  runs().push_back(this);
}

MemoryOfProcesses::~MemoryOfProcesses() { std::erase(runs(), this); }

double run_memory(double bytes) {
  const MemoryOfProcesses* run = current_run();
  if (!run || run->processes_ == 1) return bytes;
  if (run->whole_on_each_) return bytes * run->processes_;
  return full_space_run_memory(bytes, run->base_bytes_);
}

int run_processes() { return current_run() ? current_run()->processes_ : 1; }

double full_space_run_memory(double bytes, double base_bytes) {
  const double base = std::min(base_bytes, bytes);
  return bytes + (run_processes() - 1) * (base + MemoryOfProcesses::kHeldByEveryProcess * (bytes - base));
}

void require_memory(double bytes, const std::string& what, const std::string& where, const std::string& advice) {
  const Limit limit = memory_limit();
  const double need = run_memory(bytes);
  if (need <= limit.bytes) return;
  const std::string across = run_processes() > 1 ? " across " + std::to_string(run_processes()) + " processes (" +
                                                       format_bytes(bytes) + " in one process)"
                                                 : "";
  throw InputError("needs an estimated " + format_bytes(need) + " of memory" + across + " (" + what +
                       "), more than the " + format_bytes(limit.bytes) + " available (" + limit.source + "); " +
                       advice + ", or set HEMIVEM_MEMORY_LIMIT to override the limit",
                   where);
}

std::string format_bytes(double bytes) {
  static const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (!std::isfinite(bytes)) return "unlimited";
  int k = 0;
  while (bytes >= 1024.0 && k < 6) bytes /= 1024.0, ++k;
  if (bytes >= 1024.0) return sci(bytes) + " " + units[k];
  std::ostringstream s;
  s << std::fixed << std::setprecision(bytes < 10 ? 1 : 0) << bytes << " " << units[k];
  return s.str();
}

}  // namespace hemivem
