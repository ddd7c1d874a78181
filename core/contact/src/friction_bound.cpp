#include <hemivem/contact/problem.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace hemivem {

double FrictionBound::of_normal_displacement(double u_nu) const {
  if (table.empty()) return 0.0;
  if (u_nu <= table.front()[0]) return table.front()[1];
  if (u_nu >= table.back()[0]) return table.back()[1];
  const auto next = std::upper_bound(table.begin(), table.end(), u_nu,
                                     [](double x, const std::array<double, 2>& p) { return x < p[0]; });
  const auto& q = *next;
  const auto& p = *(next - 1);
  const double s = (u_nu - p[0]) / (q[0] - p[0]);
  return p[1] + s * (q[1] - p[1]);
}

double FrictionBound::bound(double u_nu, double pressure) const {
  if (kind == Kind::coulomb) return coefficient * std::max(pressure, 0.0);
  return of_normal_displacement(u_nu);
}

std::string to_string(FrictionBound::Kind kind) {
  return kind == FrictionBound::Kind::coulomb ? "coulomb" : "normal-displacement";
}

void check_friction_bound(const FrictionBound& bound, const std::string& where) {
  if (bound.kind == FrictionBound::Kind::coulomb) {
    if (!(std::isfinite(bound.coefficient) && bound.coefficient >= 0.0))
      throw InputError("the friction coefficient must be finite and >= 0, got " + std::to_string(bound.coefficient),
                       where);
    return;
  }
  if (bound.table.empty()) throw InputError("the friction bound h(u_nu) needs at least one point (u_nu, h)", where);
  for (std::size_t i = 0; i < bound.table.size(); ++i) {
    const auto& p = bound.table[i];
    if (!std::isfinite(p[0]) || !(std::isfinite(p[1]) && p[1] >= 0.0))
      throw InputError("point " + std::to_string(i + 1) + " of the friction bound h(u_nu): u_nu must be finite and h finite and >= 0",
                       where);
    if (i > 0 && !(p[0] > bound.table[i - 1][0]))
      throw InputError("the points of the friction bound h(u_nu) must have increasing u_nu (point " +
                           std::to_string(i + 1) + ")",
                       where);
  }
}

}  // namespace hemivem
