// The motion of a group of coordinates in a projected Newton iteration: see group_motion.hpp.
#include <hemivem/group_motion.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hemivem {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A group at v = 0 whose smooth gradient is gq: stuck while |gq| <= w j'(0+), else leaving 0
/// along the ray e = -gq / |gq| up to the first knot `first_knot`.
void classify_at_origin(const ContactLaw& law, double w, const Eigen::Vector2d& gq, double first_knot, GroupMotion& g) {
  const double slope0 = law.derivative(LawPart::j, 0.0, +1);
  const double m = gq.norm();
  g.e = m > 0.0 ? Eigen::Vector2d(-gq / m) : Eigen::Vector2d(1.0, 0.0);
  g.t = Eigen::Vector2d(-g.e(1), g.e(0));
  g.r_lo = 0.0;
  if (m <= w * slope0) {
    g.mode = GroupMotion::Mode::stuck;
    g.grad.setZero();
    g.r_hi = 0.0;
  } else {
    g.mode = GroupMotion::Mode::ray;
    g.grad = gq + w * slope0 * g.e;
    g.r_hi = first_knot;
    g.radial_curvature = w * law.second_derivative(LawPart::j, 0.0, +1);
  }
}

}  // namespace

Eigen::Vector2d onto_radius(const Eigen::Vector2d& x, double radius) {
  Eigen::Vector2d y = x * (radius / x.norm());
  for (const int i : {std::abs(y(0)) >= std::abs(y(1)) ? 0 : 1, std::abs(y(0)) >= std::abs(y(1)) ? 1 : 0}) {
    for (int k = 0; k < 4; ++k) {
      const double h = std::hypot(y(0), y(1));
      if (h == radius) return y;
      const double away = std::copysign(kInf, y(i));
      y(i) = std::nextafter(y(i), h < radius ? away : -away);
    }
  }
  return y;
}

GroupMotion group_motion(const ContactLaw& law, double w, const Eigen::Vector2d& v,
                         const Eigen::Vector2d& smooth_gradient, const Eigen::Matrix2d& smooth_hessian) {
  using Mode = GroupMotion::Mode;
  GroupMotion g;
  std::vector<double> knots;  // the positive kinks of the law: its knots in radius besides 0
  for (double k : law.kinks())
    if (k > 0.0) knots.push_back(k);
  std::sort(knots.begin(), knots.end());
  const Eigen::Vector2d& gq = smooth_gradient;
  const double slope0 = law.derivative(LawPart::j, 0.0, +1);
  g.v = v;
  g.r = std::hypot(v(0), v(1));
  const auto above = [&](double r) {
    const auto it = std::upper_bound(knots.begin(), knots.end(), r);
    return it == knots.end() ? kInf : *it;
  };
  const auto below = [&](double r) {
    const auto it = std::lower_bound(knots.begin(), knots.end(), r);
    return it == knots.begin() ? 0.0 : *(it - 1);
  };
  int side = 1;
  if (g.r == 0.0) {
    classify_at_origin(law, w, gq, above(0.0), g);
  } else {
    g.e = g.v / g.r;
    g.t = Eigen::Vector2d(-g.e(1), g.e(0));
    const double radial = gq.dot(g.e);
    // a norm within a few ulps of a positive kink is on it (radial scaling rounds)
    const auto on = std::find_if(knots.begin(), knots.end(), [&](double k) {
      return std::abs(g.r - k) <= 8.0 * std::numeric_limits<double>::epsilon() * k;
    });
    double slope = 0.0;
    if (on != knots.end()) {
      const double k = *on;
      const double dr = radial + w * law.derivative(LawPart::j, k, +1);
      const double dl = radial + w * law.derivative(LawPart::j, k, -1);
      const bool right = dr < 0.0, left = dl > 0.0;
      if (right && (!left || -dr >= dl)) {
        g.mode = Mode::plane;
        g.r_lo = k;
        g.r_hi = above(k);
        slope = law.derivative(LawPart::j, k, +1);
      } else if (left) {
        g.mode = Mode::plane;
        side = -1;
        g.r_lo = below(k);
        g.r_hi = k;
        slope = law.derivative(LawPart::j, k, -1);
      } else {
        g.mode = Mode::held;
        g.r_lo = g.r_hi = k;
        slope = -radial / w;  // the radial law force that balances: in [j'(k-), j'(k+)]
      }
      g.grad = g.mode == Mode::held ? Eigen::Vector2d(gq - radial * g.e) : Eigen::Vector2d(gq + w * slope * g.e);
    } else {
      g.mode = Mode::plane;
      g.grad = gq + w * law.derivative(LawPart::j, g.r, +1) * g.e;
      side = g.grad.dot(g.e) <= 0.0 ? 1 : -1;
      slope = law.derivative(LawPart::j, g.r, side);
      g.r_lo = below(g.r);
      g.r_hi = above(g.r);
    }
    g.radial_curvature = w * law.second_derivative(LawPart::j, g.r, side);
    g.tangential_curvature = w * slope / g.r;
  }
  g.lo_is_knot = g.r_lo > 0.0 || slope0 > 0.0;
  const double curvature = g.mode == Mode::held ? g.t.dot(smooth_hessian * g.t) + g.tangential_curvature
                                                : g.e.dot(smooth_hessian * g.e) + g.radial_curvature;
  g.scale = std::max({curvature, 1e-3 * smooth_hessian.diagonal().maxCoeff(), std::numeric_limits<double>::min()});
  return g;
}

void pin_group(GroupMotion& g, double eps) {
  using Mode = GroupMotion::Mode;
  g.pin = std::numeric_limits<double>::quiet_NaN();
  const double radial = g.grad.dot(g.e);
  if (g.mode == Mode::ray) {
    if (g.r_hi <= eps) g.pin = g.r_hi;
  } else if (g.mode == Mode::plane) {
    if (radial > 0.0 && g.lo_is_knot && g.r - g.r_lo <= eps)
      g.pin = g.r_lo;
    else if (radial < 0.0 && g.r_hi - g.r <= eps)
      g.pin = g.r_hi;
  }
}

Eigen::Vector2d group_trial(const GroupMotion& g, const Eigen::Vector2d& dg, double t) {
  using Mode = GroupMotion::Mode;
  switch (g.mode) {
    case Mode::stuck: return g.v;
    case Mode::ray: {
      const double length = t * dg.dot(g.e);
      return length >= g.r_hi ? onto_radius(g.e, g.r_hi) : Eigen::Vector2d(std::max(length, 0.0) * g.e);
    }
    case Mode::held: {
      const Eigen::Vector2d x = g.v + t * dg;
      return x.norm() > 0.0 ? onto_radius(x, g.r_lo) : g.v;
    }
    case Mode::plane: break;
  }
  const Eigen::Vector2d x = g.v + t * dg;
  if (!std::isnan(g.pin)) {
    if (g.pin == 0.0) return Eigen::Vector2d::Zero();  // onto the cone point at any step
    if (!(x.norm() > 0.0)) return g.v;
    return t == 1.0 ? onto_radius(x, g.pin) : Eigen::Vector2d(x * ((g.r + t * (g.pin - g.r)) / x.norm()));
  }
  if (g.r_lo == 0.0 && g.lo_is_knot && x.dot(g.e) <= 0.0) return Eigen::Vector2d::Zero();
  const double m = x.norm();
  if (m < g.r_lo) return m > 0.0 ? onto_radius(x, g.r_lo) : onto_radius(g.e, g.r_lo);
  if (m > g.r_hi) return onto_radius(x, g.r_hi);
  return x;
}

}  // namespace hemivem
