#include <hemivem/mesh/generators3d.hpp>

#include "box_grid.hpp"

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <sstream>

namespace hemivem {

namespace detail {

namespace {
std::string number(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}
}  // namespace

void check_box_grid(const char* generator, GridSize3 n, const Box& d) {
  constexpr int max_cells = 1000;
  for (const int k : {n.nx, n.ny, n.nz})
    if (k < 1 || k > max_cells)
      throw InputError(std::string(generator) + ": the number of cells along each axis must be between 1 and " +
                       std::to_string(max_cells) + " (got " + n.text() + ")");
  const std::string got = " (got [" + number(d.x0) + ", " + number(d.x1) + "] x [" + number(d.y0) + ", " +
                          number(d.y1) + "] x [" + number(d.z0) + ", " + number(d.z1) + "])";
  double scale = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(d.lower(a)) || !std::isfinite(d.upper(a)) || !std::isfinite(d.size(a)) || !(d.size(a) > 0.0))
      throw InputError(std::string(generator) +
                       ": the domain must be a box [x0,x1] x [y0,y1] x [z0,z1] with finite x0 < x1, y0 < y1 and z0 < z1" +
                       got);
    scale = std::max({scale, std::abs(d.lower(a)), std::abs(d.upper(a))});
  }
  if (scale > 1e100)
    throw InputError(std::string(generator) + ": the domain's coordinates must be at most 1e100 in magnitude" + got);
  const double cx = d.size(0) / n.nx, cy = d.size(1) / n.ny, cz = d.size(2) / n.nz;
  if (!(std::min({cx, cy, cz}) >= 1e-9 * scale) || !(cx * cy * cz >= 1e-250))
    throw InputError(std::string(generator) + ": the cells of the domain with n = " + n.text() +
                     " are too small for double precision (cell sides must be at least 1e-9 of the largest "
                     "|coordinate| and the cell volume at least 1e-250)" + got);
}

double box_grid_coordinate(double a, double b, long i, long n) {
  if (i == n) return b;
  return a + (b - a) * static_cast<double>(i) / static_cast<double>(n);
}

}  // namespace detail

namespace {

std::vector<Vec3> grid_vertices(GridSize3 n, const Box& d) {
  std::vector<Vec3> v;
  v.reserve(static_cast<std::size_t>(n.nx + 1) * (n.ny + 1) * (n.nz + 1));
  for (int k = 0; k <= n.nz; ++k)
    for (int j = 0; j <= n.ny; ++j)
      for (int i = 0; i <= n.nx; ++i)
        v.emplace_back(detail::box_grid_coordinate(d.x0, d.x1, i, n.nx), detail::box_grid_coordinate(d.y0, d.y1, j, n.ny),
                       detail::box_grid_coordinate(d.z0, d.z1, k, n.nz));
  return v;
}

// the 8 corners of box (i, j, k), corner b = (b & 1, b >> 1 & 1, b >> 2 & 1)
std::array<int, 8> box_corners(GridSize3 n, int i, int j, int k) {
  std::array<int, 8> c{};
  for (int b = 0; b < 8; ++b)
    c[static_cast<std::size_t>(b)] = ((k + (b >> 2 & 1)) * (n.ny + 1) + j + (b >> 1 & 1)) * (n.nx + 1) + i + (b & 1);
  return c;
}

// the boxes of the grid, each with its faces outward: x0, x1, y0, y1, z0, z1
std::vector<CellFaces> cube_cells(GridSize3 n, const detail::PieceBoxes& keep = {}) {
  std::vector<CellFaces> cells;
  cells.reserve(static_cast<std::size_t>(n.nx) * n.ny * n.nz);
  for (int k = 0; k < n.nz; ++k)
    for (int j = 0; j < n.ny; ++j)
      for (int i = 0; i < n.nx; ++i) {
        if (!keep(i, j, k)) continue;
        const auto c = box_corners(n, i, j, k);
        cells.push_back({{c[0], c[4], c[6], c[2]}, {c[1], c[3], c[7], c[5]}, {c[0], c[1], c[5], c[4]},
                         {c[2], c[6], c[7], c[3]}, {c[0], c[2], c[3], c[1]}, {c[4], c[5], c[7], c[6]}});
      }
  return cells;
}

// each box of the grid cut into six tetrahedra, the six paths 0 -> 7 along the box's edges, one
// axis at a time (x = 1, y = 2, z = 4)
std::vector<CellFaces> tetrahedron_cells(GridSize3 n, const detail::PieceBoxes& keep = {}) {
  std::vector<CellFaces> cells;
  cells.reserve(6 * static_cast<std::size_t>(n.nx) * n.ny * n.nz);
  static constexpr std::array<std::array<int, 3>, 6> orders = {
      {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}}};
  for (int k = 0; k < n.nz; ++k)
    for (int j = 0; j < n.ny; ++j)
      for (int i = 0; i < n.nx; ++i) {
        if (!keep(i, j, k)) continue;
        const auto c = box_corners(n, i, j, k);
        for (const auto& o : orders) {
          int a = c[0], b = c[static_cast<std::size_t>(o[0])], d = c[static_cast<std::size_t>(o[0] + o[1])], e = c[7];
          // positive orientation: det(b - a, d - a, e - a) > 0 holds for the even permutations
          const bool even = (o[0] == 1 && o[1] == 2) || (o[0] == 2 && o[1] == 4) || (o[0] == 4 && o[1] == 1);
          if (!even) std::swap(b, d);
          cells.push_back({{a, d, b}, {a, b, e}, {a, e, d}, {b, d, e}});
        }
      }
  return cells;
}

// The grid of the coordinate lists, checked (InputError naming `what`), and its points.
GridSize3 list_grid(const char* what, const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<double>& z, std::vector<Vec3>& vertices) {
  const std::vector<double>* axes[3] = {&x, &y, &z};
  for (int a = 0; a < 3; ++a) {
    const auto& c = *axes[a];
    const std::string which = std::string(what) + ": the " + "xyz"[a] + " coordinates";
    if (c.size() < 2) throw InputError(which + " need at least two values");
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!std::isfinite(c[i])) throw InputError(which + " must be finite");
      if (i > 0 && !(c[i] > c[i - 1])) throw InputError(which + " must increase strictly (value " + std::to_string(i) + ")");
    }
  }
  const GridSize3 n(static_cast<int>(x.size()) - 1, static_cast<int>(y.size()) - 1, static_cast<int>(z.size()) - 1);
  detail::check_box_grid(what, n, Box{x.front(), x.back(), y.front(), y.back(), z.front(), z.back()});
  vertices.clear();
  for (int k = 0; k <= n.nz; ++k)
    for (int j = 0; j <= n.ny; ++j)
      for (int i = 0; i <= n.nx; ++i)
        vertices.emplace_back(x[static_cast<std::size_t>(i)], y[static_cast<std::size_t>(j)], z[static_cast<std::size_t>(k)]);
  return n;
}

}  // namespace

std::string GridSize3::text() const {
  return nx == ny && ny == nz ? std::to_string(nx)
                              : "[" + std::to_string(nx) + ", " + std::to_string(ny) + ", " + std::to_string(nz) + "]";
}

Mesh3D make_cubes(GridSize3 n, const Box& domain) {
  detail::check_box_grid("cubes mesh", n, domain);
  return Mesh3D(grid_vertices(n, domain), cube_cells(n));
}

Mesh3D make_cubes(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z) {
  std::vector<Vec3> vertices;
  const GridSize3 n = list_grid("cubes mesh", x, y, z, vertices);
  return Mesh3D(std::move(vertices), cube_cells(n));
}

Mesh3D make_tetrahedra(GridSize3 n, const Box& domain) {
  detail::check_box_grid("tetrahedra mesh", n, domain);
  return Mesh3D(grid_vertices(n, domain), tetrahedron_cells(n));
}

Mesh3D make_tetrahedra(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
                       const std::function<Vec3(const Vec3&)>& place) {
  std::vector<Vec3> vertices;
  const GridSize3 n = list_grid("tetrahedra mesh", x, y, z, vertices);
  if (place)
    for (Vec3& v : vertices) v = place(v);
  return Mesh3D(std::move(vertices), tetrahedron_cells(n));
}

Mesh3D make_mesh3d_piece(std::string_view generator, GridSize3 n, const Box& domain, const BoxPiece& piece) {
  detail::require_piece_generator(generator, 3);
  const bool cubes = generator == "cubes";
  detail::check_box_grid(cubes ? "cubes mesh" : "tetrahedra mesh", n, domain);
  const detail::PieceBoxes keep(generator, 3, {n.nx, n.ny, n.nz}, piece);
  return Mesh3D(grid_vertices(n, domain), cubes ? cube_cells(n, keep) : tetrahedron_cells(n, keep));
}

const std::vector<std::string>& mesh3d_generator_names() {
  static const std::vector<std::string> names = {"cubes", "tetrahedra", "voronoi"};
  return names;
}

Mesh3D make_mesh3d(std::string_view generator, GridSize3 n, const Box& domain, std::uint64_t seed,
                   const RowDistribution* processes) {
  if (generator == "cubes") return make_cubes(n, domain);
  if (generator == "tetrahedra") return make_tetrahedra(n, domain);
  if (generator == "voronoi") {
    VoronoiOptions options;
    options.seed = seed;
    options.processes = processes;
    return make_voronoi3d(n, domain, options);
  }
  std::string names;
  for (const auto& name : mesh3d_generator_names()) names += (names.empty() ? "" : ", ") + name;
  throw InputError("unknown 3D mesh generator '" + std::string(generator) + "'; expected one of " + names);
}

}  // namespace hemivem
