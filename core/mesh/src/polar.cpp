// make_polar (generators.hpp): the cells of a polar grid, for rings, disks and their sectors.
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/box_piece.hpp>
#include <hemivem/error.hpp>

#include "box_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace hemivem {

namespace {

/// cos and sin of `angle`, exact (0, +-1) at the multiples of pi/2 to round-off, so that the
/// vertices on an axis lie on it.
Vec2 direction(double angle) {
  const double quarter = angle / (0.5 * std::numbers::pi);
  if (std::abs(quarter - std::round(quarter)) <= 1e-14 * std::max(1.0, std::abs(quarter))) {
    const long k = ((static_cast<long>(std::llround(quarter)) % 4) + 4) % 4;
    return k == 0 ? Vec2(1, 0) : k == 1 ? Vec2(0, 1) : k == 2 ? Vec2(-1, 0) : Vec2(0, -1);
  }
  return {std::cos(angle), std::sin(angle)};
}

void require_increasing(const std::vector<double>& values, const char* what) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k]))
      throw InputError(std::string("make_polar: ") + what + "[" + std::to_string(k) + "] is not finite");
    if (k > 0 && !(values[k] > values[k - 1]))
      throw InputError(std::string("make_polar: the ") + what + " must increase, but " + what + "[" +
                       std::to_string(k) + "] = " + std::to_string(values[k]) + " follows " +
                       std::to_string(values[k - 1]));
  }
}

/// A polar grid's layout (make_polar), checked: m rings, n sectors, whether the angles make a full
/// turn and the first radius is 0.
struct PolarLayout {
  int m = 0, n = 0;
  bool full = false, disk = false;

  PolarLayout(const std::vector<double>& radii, const std::vector<double>& angles) {
    if (radii.size() < 2 || angles.size() < 2)
      throw InputError("make_polar: at least two radii and two angles are needed (one ring of cells), got " +
                       std::to_string(radii.size()) + " and " + std::to_string(angles.size()));
    if (radii.size() > 20001 || angles.size() > 20001) throw InputError("make_polar: at most 20001 radii and 20001 angles");
    require_increasing(radii, "radii");
    require_increasing(angles, "angles");
    if (radii.front() < 0.0) throw InputError("make_polar: radii[0] = " + std::to_string(radii.front()) + " is negative");
    const double span = angles.back() - angles.front(), two_pi = 2.0 * std::numbers::pi;
    if (span > two_pi * (1.0 + 1e-14))
      throw InputError("make_polar: the angles span " + std::to_string(span) + " radians, more than a full turn");
    full = span >= two_pi * (1.0 - 1e-14);  // the last angle is the first
    disk = radii.front() == 0.0;            // the centre is one vertex
    m = static_cast<int>(radii.size()) - 1;
    n = static_cast<int>(angles.size()) - 1;
  }

  /// Its grid of boxes: sector j along x, ring i along y.
  std::array<int, 3> counts() const { return {n, m, 1}; }
  GridClosure closure() const { return {full, disk}; }
  /// The cells of the boxes `keep` makes, in the mesh's order: sector by sector, ring by ring.
  template <class Visit>
  void for_each_cell(const detail::PieceBoxes& keep, Visit&& visit) const {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < m; ++i)
        if (keep(j, i, 0)) visit(i, j);
  }
};

/// The polar grid's mesh of the boxes `keep` makes (all by default): every vertex, and the cells
/// and edge groups of those boxes.
Mesh polar_mesh(const Vec2& center, const std::vector<double>& radii, const std::vector<double>& angles,
                const detail::PieceBoxes& keep = {}) {
  const PolarLayout grid(radii, angles);
  if (!center.allFinite()) throw InputError("make_polar: the center is not finite");
  const bool full = grid.full, disk = grid.disk;
  const int m = grid.m, n = grid.n;
  const BoxGridVertices numbering("polar", 2, grid.counts(), grid.closure());
  std::vector<Vec2> vertices;
  vertices.reserve(static_cast<std::size_t>(numbering.count()));
  for (long long v = 0; v < numbering.count(); ++v) {
    const auto [j, i, k] = numbering.point(v);
    vertices.push_back(center + radii[static_cast<std::size_t>(i)] * direction(angles[static_cast<std::size_t>(j)]));
  }
  const auto at = [&](int i, int j) { return static_cast<int>(numbering.corner({j, i, 0})); };
  std::vector<std::vector<int>> cells;
  grid.for_each_cell(keep, [&](int i, int j) {
    if (disk && i == 0)
      cells.push_back({at(0, 0), at(1, j), at(1, j + 1)});
    else
      cells.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  });
  Mesh mesh(std::move(vertices), std::move(cells));
  // the boundary's parts by the rows and columns of their ends: a piece's boundary inside the
  // whole mesh joins no two vertices of one of them
  std::vector<int> inner, outer, start, end;
  for (int e : mesh.boundary_edges()) {
    const auto a = numbering.point(mesh.edge(e).v0), b = numbering.point(mesh.edge(e).v1);
    const bool centre_a = disk && mesh.edge(e).v0 == 0, centre_b = disk && mesh.edge(e).v1 == 0;
    if (a[1] == m && b[1] == m)
      outer.push_back(e);
    else if (!disk && a[1] == 0 && b[1] == 0)
      inner.push_back(e);
    else if ((a[0] == 0 || centre_a) && (b[0] == 0 || centre_b))
      start.push_back(e);
    else if ((a[0] == n || centre_a) && (b[0] == n || centre_b))
      end.push_back(e);
  }
  mesh.set_edge_group("outer", std::move(outer));
  if (!disk) mesh.set_edge_group("inner", std::move(inner));
  if (!full) {
    mesh.set_edge_group("start", std::move(start));
    mesh.set_edge_group("end", std::move(end));
  }
  return mesh;
}

}  // namespace

Mesh make_polar(const Vec2& center, const std::vector<double>& radii, const std::vector<double>& angles) {
  return polar_mesh(center, radii, angles);
}

Mesh make_polar_piece(const Vec2& center, const std::vector<double>& radii, const std::vector<double>& angles,
                      const BoxPiece& piece) {
  const PolarLayout grid(radii, angles);
  return polar_mesh(center, radii, angles, detail::PieceBoxes("polar", 2, grid.counts(), piece, grid.closure()));
}

GridClosure polar_closure(const std::vector<double>& radii, const std::vector<double>& angles) {
  return PolarLayout(radii, angles).closure();
}

std::vector<int> polar_piece_cells(const std::vector<double>& radii, const std::vector<double>& angles,
                                   const BoxPiece& piece) {
  const PolarLayout grid(radii, angles);
  const detail::PieceBoxes keep("polar", 2, grid.counts(), piece, grid.closure());
  std::vector<int> out;
  grid.for_each_cell(keep, [&](int i, int j) { out.push_back(j * grid.m + i); });
  return out;
}

}  // namespace hemivem

namespace hemivem {

std::vector<double> graded_steps(double from, double to, int n, double ratio) {
  if (n < 1) throw InputError("graded_steps: n must be >= 1, got " + std::to_string(n));
  if (!(ratio >= 1.0) || !std::isfinite(ratio))
    throw InputError("graded_steps: the ratio must be >= 1, got " + std::to_string(ratio));
  if (!std::isfinite(from) || !std::isfinite(to)) throw InputError("graded_steps: the ends must be finite");
  // the partial sums of 1, ratio, ratio^2, ... scaled to the length
  std::vector<double> sums(static_cast<std::size_t>(n) + 1, 0.0);
  double step = 1.0;
  for (int k = 1; k <= n; ++k) {
    sums[static_cast<std::size_t>(k)] = sums[static_cast<std::size_t>(k) - 1] + step;
    step *= ratio;
  }
  std::vector<double> out(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k) out[k] = from + (to - from) * (sums[k] / sums.back());
  out.front() = from;
  out.back() = to;
  return out;
}

std::array<std::vector<double>, 2> polar_grid(const std::array<double, 2>& radii, const std::array<double, 2>& angles,
                                              int n_radial, int n_around, double ratio, std::optional<double> focus) {
  if (!(radii[0] >= 0.0 && radii[0] < radii[1]) || !std::isfinite(radii[1]))
    throw InputError("polar: the radii [r0, r1] need 0 <= r0 < r1, got [" + std::to_string(radii[0]) + ", " +
                     std::to_string(radii[1]) + "]");
  if (!(angles[0] < angles[1] && angles[1] - angles[0] <= 360.0) || !std::isfinite(angles[0]))
    throw InputError("polar: the angles [a0, a1] need a0 < a1 <= a0 + 360 (degrees), got [" +
                     std::to_string(angles[0]) + ", " + std::to_string(angles[1]) + "]");
  if (focus && !(*focus >= angles[0] && *focus <= angles[1]))
    throw InputError("polar: the focus " + std::to_string(*focus) + " lies outside the angles");
  if (n_radial < 1 || n_around < 1) throw InputError("polar: n = [radial, around] needs at least one cell each");
  if (focus && *focus > angles[0] && *focus < angles[1] && n_around < 2)
    throw InputError("polar: a focus between the angles needs at least two cells around, one on each side");
  std::vector<double> r = graded_steps(radii[1], radii[0], n_radial, ratio);
  std::reverse(r.begin(), r.end());
  const double degree = std::numbers::pi / 180.0;
  std::vector<double> a;
  if (!focus) {
    a = graded_steps(angles[0], angles[1], n_around, 1.0);
  } else {
    const double span = angles[1] - angles[0];
    int left = static_cast<int>(std::lround(n_around * (*focus - angles[0]) / span));
    if (*focus > angles[0]) left = std::max(left, 1);
    if (*focus < angles[1]) left = std::min(left, n_around - 1);
    const int right = n_around - left;
    if (left > 0) {
      a = graded_steps(*focus, angles[0], left, ratio);
      std::reverse(a.begin(), a.end());
    } else {
      a = {*focus};
    }
    if (right > 0) {
      const std::vector<double> b = graded_steps(*focus, angles[1], right, ratio);
      a.insert(a.end(), b.begin() + 1, b.end());
    }
  }
  for (double& x : a) x *= degree;
  return {r, a};
}

}  // namespace hemivem
