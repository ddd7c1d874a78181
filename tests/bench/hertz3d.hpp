// A rigid sphere pressed into an elastic block, the three-dimensional Hertz problem
// (docs/three-dimensions.md): a quarter model on a graded mesh of boxes, shared by the test of
// its accuracy and the program that measures how the error falls with h.
#pragma once

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/mesh/generators3d.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <numbers>
#include <vector>

namespace hemivem::hertz3d {

struct Setup {
  double young = 100.0, poisson = 0.3;
  double radius = 1.0;        ///< R, of the sphere
  double indentation = 0.0025;  ///< d: a = sqrt(R d) = 0.05
  double size = 1.0;          ///< the block [0, L]^3 (a quarter of [-L, L]^2 x [0, L])
  double h_over_a = 1.0 / 8;  ///< the mesh size near the contact, relative to a
  double growth = 1.25;       ///< the ratio of neighbouring cells away from it
  double a() const { return std::sqrt(radius * indentation); }
  double e_star() const { return young / (1.0 - poisson * poisson); }
  /// P = (4/3) E* R^(1/2) d^(3/2) for the whole sphere
  double force() const { return 4.0 / 3.0 * e_star() * std::sqrt(radius) * std::pow(indentation, 1.5); }
  double p0() const { return 3.0 * force() / (2.0 * std::numbers::pi * a() * a()); }
};

/// Coordinates from 0: steps of h up to 1.5 a, then growing by `growth` up to L.
inline std::vector<double> graded(const Setup& s) {
  const double h = s.h_over_a * s.a();
  std::vector<double> x{0.0};
  double step = h;
  while (x.back() < s.size - 1e-12) {
    if (x.back() >= 1.5 * s.a()) step *= s.growth;
    x.push_back(std::min(s.size, x.back() + step));
    if (s.size - x.back() < 0.3 * step) x.back() = s.size;
  }
  return x;
}

inline Mesh3D mesh(const Setup& s) {
  const std::vector<double> x = graded(s);
  std::vector<double> z;
  for (auto it = x.rbegin(); it != x.rend(); ++it) z.push_back(s.size - *it);
  return make_cubes(x, x, z);
}

inline ContactProblem3D problem(const Setup& s, const Mesh3D& m) {
  const Box box = m.bounding_box();
  ContactProblem3D p;
  p.elasticity.mesh = &m;
  p.elasticity.materials = MaterialTable(Material{s.young, s.poisson}, PlaneModel::strain);
  p.elasticity.dirichlet.push_back({select_box_side(m, box, "x0"), {}, {true, false, false}, "symmetry x"});
  p.elasticity.dirichlet.push_back({select_box_side(m, box, "y0"), {}, {false, true, false}, "symmetry y"});
  p.elasticity.dirichlet.push_back({select_box_side(m, box, "bottom"), {}, {true, true, true}, "base"});
  ContactPart3D contact;
  contact.name = "contact";
  contact.facets = select_box_side(m, box, "top");
  Obstacle3D sphere;
  sphere.shape = Obstacle3D::Shape::sphere;
  sphere.center = Vec3(0.0, 0.0, s.size + s.radius - s.indentation);
  sphere.radius = s.radius;
  contact.obstacle = sphere;
  contact.law = zero_law();
  contact.constraint = ConstraintKind::one_sided;
  p.parts.push_back(std::move(contact));
  return p;
}

struct Measured {
  int nodes_in_disk = 0;  ///< contact nodes of the quarter model with r < a (Hertz's a)
  int full_disk = 0;      ///< the same for the whole disk, by symmetry
  int nodes_in_contact = 0;
  double a = 0.0;         ///< from the least-squares fit p^2 = p0^2 (1 - r^2/a^2) over the pressed nodes
  double p0 = 0.0;        ///< the pressure of the node at the centre
  double force = 0.0;     ///< 4 x the quarter model's contact resultant
};

inline Measured measure(const Setup& s, const ContactSolution3D& sol) {
  Measured m;
  Eigen::MatrixXd A(0, 2);
  Eigen::VectorXd b(0);
  for (const ContactNode3D& n : sol.contact) {
    const double r = n.x.head<2>().norm();
    if (r < s.a()) {
      ++m.nodes_in_disk;
      m.full_disk += (n.x.x() > 0.0 ? 2 : 1) * (n.x.y() > 0.0 ? 2 : 1);
    }
    if (r == 0.0) m.p0 = n.pressure();
    if (!(n.force() > 0.0)) continue;
    ++m.nodes_in_contact;
    m.force += 4.0 * n.force();
    // the nodes on the symmetry planes stand for half (or a quarter) of their disk's share: they
    // still carry the pressure p, the fit uses it
    A.conservativeResize(A.rows() + 1, 2);
    b.conservativeResize(b.size() + 1);
    A.row(A.rows() - 1) << 1.0, -r * r;
    b(b.size() - 1) = n.pressure() * n.pressure();
  }
  if (A.rows() >= 2) {
    const Eigen::Vector2d c = A.colPivHouseholderQr().solve(b);  // p0^2, p0^2 / a^2
    m.a = std::sqrt(c(0) / c(1));
  }
  return m;
}

}  // namespace hemivem::hertz3d
