#include <hemivem/mesh/finer_grid.hpp>

#include <array>
#include <string>

#include <hemivem/error.hpp>

namespace hemivem {
namespace {

// The points of the grid of 2 counts boxes (counts[2] = 0 in the plane), each the mean of the
// coarse points at floor(i / 2) and ceil(i / 2) along every axis.
Eigen::VectorXd finer(const Eigen::VectorXd& coarse, std::array<long, 3> counts, int components) {
  if (components < 1) throw InputError("values on a grid need at least one number per point");
  const std::array<long, 3> points{counts[0] + 1, counts[1] + 1, counts[2] + 1};
  const long c = components;
  if (coarse.size() != points[0] * points[1] * points[2] * c)
    throw InputError("values on the grid of " + std::to_string(points[0] * points[1] * points[2]) + " points with " +
                     std::to_string(c) + " numbers each take " + std::to_string(points[0] * points[1] * points[2] * c) +
                     " numbers, got " + std::to_string(coarse.size()));
  const std::array<long, 3> fine{2 * counts[0] + 1, 2 * counts[1] + 1, 2 * counts[2] + 1};
  Eigen::VectorXd out(fine[0] * fine[1] * fine[2] * c);
  for (long k = 0; k < fine[2]; ++k)
    for (long j = 0; j < fine[1]; ++j)
      for (long i = 0; i < fine[0]; ++i) {
        auto v = out.segment((((k * fine[1]) + j) * fine[0] + i) * c, c);
        v.setZero();
        int corners = 0;
        for (long dk = 0; dk <= (k & 1); ++dk)
          for (long dj = 0; dj <= (j & 1); ++dj)
            for (long di = 0; di <= (i & 1); ++di, ++corners)
              v += coarse.segment((((k / 2 + dk) * points[1] + j / 2 + dj) * points[0] + i / 2 + di) * c, c);
        v /= corners;
      }
  return out;
}

}  // namespace

Eigen::VectorXd values_on_finer_grid(const Eigen::VectorXd& coarse, GridSize n, int components) {
  return finer(coarse, {n.nx, n.ny, 0}, components);
}

Eigen::VectorXd values_on_finer_grid(const Eigen::VectorXd& coarse, GridSize3 n, int components) {
  return finer(coarse, {n.nx, n.ny, n.nz}, components);
}

}  // namespace hemivem
