// A block on a frictionless rigid plane pushed down on its top: the three-dimensional contact
// problem with an exact (linear) solution, shared by the contact and error-estimate tests.
#pragma once

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>

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

}  // namespace hemivem::test
