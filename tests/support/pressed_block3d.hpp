// A block on a frictionless rigid plane pushed down on its top: the three-dimensional contact
// problem with an exact (linear) solution, shared by the contact and error-estimate tests; and
// Example 4.1 in three dimensions.
#pragma once

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/linear_backends.hpp>

namespace hemivem::test {

inline constexpr double pressed_block_young = 100.0, pressed_block_poisson = 0.3, pressed_block_depth = 0.01;

/// The box `box` on the rigid plane z = 0 (frictionless, one-sided), symmetry planes x0 and y0,
/// its top pushed down by pressed_block_depth (the normal component only): uniaxial stress.
inline ContactProblem3D pressed_block(const Mesh3D& mesh, const Box& box) {
  ContactProblem3D p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(Material{pressed_block_young, pressed_block_poisson}, PlaneModel::strain);
  p.elasticity.dirichlet.push_back({select_box_side(mesh, box, "x0"), {}, {true, false, false}, "x0"});
  p.elasticity.dirichlet.push_back({select_box_side(mesh, box, "y0"), {}, {false, true, false}, "y0"});
  p.elasticity.dirichlet.push_back({select_box_side(mesh, box, "top"),
                                    [](const Vec3&) { return Vec3(0, 0, -pressed_block_depth); },
                                    {false, false, true},
                                    "top"});
  ContactPart3D contact;
  contact.name = "contact";
  contact.facets = select_box_side(mesh, box, "bottom");
  Obstacle3D plane;
  plane.point = Vec3::Zero();
  plane.normal = Vec3(0, 0, 1);
  contact.obstacle = plane;
  contact.law = zero_law();
  contact.constraint = ConstraintKind::one_sided;
  p.parts.push_back(std::move(contact));
  return p;
}

/// Example 4.1 in three dimensions on `mesh` (a box): clamped at its sides x0 and x1, pressed
/// down by (0, 0, -8) on its top, on the paper's foundation behind g = 0.02 (the box
/// constraint) on its bottom; lengths scaled by s (Young's modulus 65 s) and Poisson's ratio
/// `poisson`.
inline ContactProblem3D example_4_1_3d(const Mesh3D& mesh, double s = 1.0, double poisson = 0.29) {
  const Box box = mesh.bounding_box();
  ContactProblem3D p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(Material{65.0 * s, poisson}, PlaneModel::strain);
  std::vector<int> sides = select_box_side(mesh, box, "x0");
  const std::vector<int> x1 = select_box_side(mesh, box, "x1");
  sides.insert(sides.end(), x1.begin(), x1.end());
  p.elasticity.dirichlet.push_back({sides, {}, {true, true, true}, "clamped"});
  TractionLoad3D top;
  top.facets = select_box_side(mesh, box, "top");
  top.traction = [](const Vec3&) { return Vec3(0.0, 0.0, -8.0); };
  p.elasticity.tractions.push_back(top);
  ContactPart3D contact;
  contact.name = "contact";
  contact.facets = select_box_side(mesh, box, "bottom");
  contact.gap = [](const Vec3&) { return 0.02; };
  contact.law = paper_law();
  contact.constraint = ConstraintKind::box;
  p.parts.push_back(std::move(contact));
  return p;
}

/// The Eigen factorization, the engine the 3D tests solve with.
inline std::unique_ptr<SparseFactorization> eigen_engine() {
  FactorizationOptions o;
  o.engine = "eigen";
  return make_factorization(o);
}

}  // namespace hemivem::test
