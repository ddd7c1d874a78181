// Lame's solution of two rings pressed into each other by an interference fit, in plane strain:
// the closed form the interference tests of two bodies compare with.
#pragma once

#include <hemivem/vem/material.hpp>

#include <Eigen/Dense>

#include <array>

namespace hemivem::test {

/// A ring of radii a and b + delta inside a ring of radii b and c.
struct LameRings {
  double a = 0.5, b = 1.0, c = 2.0, delta = 1e-3;
  Material inner{2.0, 0.3}, outer{1.0, 0.25};
};

/// The pressure on the outer ring's inner surface and the radial displacement of its outer
/// surface: u_r = A r + B / r in each ring, sigma_rr = 2 (lambda + mu) A - 2 mu B / r^2; free
/// surfaces at a and c, the radial displacements closing the overlap delta (the inner ring at
/// b + delta, the outer at b), and the forces per unit angle equal and opposite.
inline std::array<double, 2> lame_interference(const LameRings& r) {
  const auto moduli = [](const Material& m) {
    const double mu = m.young / (2.0 * (1.0 + m.poisson));
    const double lambda = m.young * m.poisson / ((1.0 + m.poisson) * (1.0 - 2.0 * m.poisson));
    return std::array<double, 2>{2.0 * (lambda + mu), 2.0 * mu};
  };
  const auto [ki, mi] = moduli(r.inner);
  const auto [ko, mo] = moduli(r.outer);
  const double s = r.b + r.delta;
  // unknowns (A1, B1, A2, B2)
  Eigen::Matrix4d m;
  Eigen::Vector4d rhs;
  m << ki, -mi / (r.a * r.a), 0, 0,                                  // sigma_rr of the inner ring at a: 0
      0, 0, ko, -mo / (r.c * r.c),                                   // sigma_rr of the outer ring at c: 0
      -s, -1.0 / s, r.b, 1.0 / r.b,                                  // u_outer(b) - u_inner(s) = delta
      s * ki, -s * mi / (s * s), -r.b * ko, r.b * mo / (r.b * r.b);  // s sigma_inner(s) = b sigma_outer(b)
  rhs << 0, 0, r.delta, 0;
  const Eigen::Vector4d x = m.partialPivLu().solve(rhs);
  return {-(ko * x(2) - mo * x(3) / (r.b * r.b)), x(2) * r.c + x(3) / r.c};
}

}  // namespace hemivem::test
