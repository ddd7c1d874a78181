// make_polar (generators.hpp): the cells of a polar grid, for rings, disks and their sectors.
#include <hemivem/mesh/generators.hpp>
#include <hemivem/error.hpp>

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

}  // namespace

Mesh make_polar(const Vec2& center, const std::vector<double>& radii, const std::vector<double>& angles) {
  if (radii.size() < 2 || angles.size() < 2)
    throw InputError("make_polar: at least two radii and two angles are needed (one ring of cells), got " +
                     std::to_string(radii.size()) + " and " + std::to_string(angles.size()));
  if (radii.size() > 20001 || angles.size() > 20001)
    throw InputError("make_polar: at most 20001 radii and 20001 angles");
  require_increasing(radii, "radii");
  require_increasing(angles, "angles");
  if (!center.allFinite()) throw InputError("make_polar: the center is not finite");
  if (radii.front() < 0.0) throw InputError("make_polar: radii[0] = " + std::to_string(radii.front()) + " is negative");
  const double span = angles.back() - angles.front(), two_pi = 2.0 * std::numbers::pi;
  if (span > two_pi * (1.0 + 1e-14))
    throw InputError("make_polar: the angles span " + std::to_string(span) + " radians, more than a full turn");
  const bool full = span >= two_pi * (1.0 - 1e-14);  // the last angle is the first
  const bool disk = radii.front() == 0.0;            // the centre is one vertex
  const int m = static_cast<int>(radii.size()) - 1, n = static_cast<int>(angles.size()) - 1;
  const int columns = full ? n : n + 1;  // distinct angles of vertices
  std::vector<Vec2> vertices;
  if (disk) vertices.push_back(center);
  const int first_ring = disk ? 1 : 0;
  for (int i = first_ring; i <= m; ++i)
    for (int j = 0; j < columns; ++j)
      vertices.push_back(center + radii[static_cast<std::size_t>(i)] * direction(angles[static_cast<std::size_t>(j)]));
  const auto at = [&](int i, int j) {
    if (full) j %= n;
    return disk && i == 0 ? 0 : (i - first_ring) * columns + j + (disk ? 1 : 0);
  };
  std::vector<std::vector<int>> cells;
  cells.reserve(static_cast<std::size_t>(m) * static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) {
      if (disk && i == 0)
        cells.push_back({at(0, 0), at(1, j), at(1, j + 1)});
      else
        cells.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  Mesh mesh(std::move(vertices), std::move(cells));
  // the boundary's parts by the rows and columns of their ends
  std::vector<int> ring(static_cast<std::size_t>(mesh.num_vertices()), -1), column(ring.size(), -1);
  for (int i = first_ring; i <= m; ++i)
    for (int j = 0; j < columns; ++j) {
      ring[static_cast<std::size_t>(at(i, j))] = i;
      column[static_cast<std::size_t>(at(i, j))] = j;
    }
  std::vector<int> inner, outer, start, end;
  for (int e : mesh.boundary_edges()) {
    const int a = mesh.edge(e).v0, b = mesh.edge(e).v1;
    const auto ra = ring[static_cast<std::size_t>(a)], rb = ring[static_cast<std::size_t>(b)];
    const auto ca = column[static_cast<std::size_t>(a)], cb = column[static_cast<std::size_t>(b)];
    if (ra == m && rb == m)
      outer.push_back(e);
    else if (!disk && ra == 0 && rb == 0)
      inner.push_back(e);
    else if ((ca == 0 || ca < 0) && (cb == 0 || cb < 0))
      start.push_back(e);
    else if ((ca == n || ca < 0) && (cb == n || cb < 0))
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
