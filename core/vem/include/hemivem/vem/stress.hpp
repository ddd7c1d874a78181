// Element stresses of a displacement: the stress of the projection Pi u_h on each element.
#pragma once

#include <vector>

#include <Eigen/Core>

#include <hemivem/vem/material.hpp>
#include <hemivem/mesh/mesh.hpp>

namespace hemivem {

/// The projected stress (xx, yy, zz, xy) of one element.
struct ElementStress {
  double xx = 0.0, yy = 0.0, zz = 0.0, xy = 0.0;
  /// sqrt(((xx - yy)^2 + (yy - zz)^2 + (zz - xx)^2) / 2 + 3 xy^2).
  double von_mises() const;
};

/// Per element: the stress of Pi u_h (constant on the element) with the material of the
/// element's region; sigma_zz = lambda (eps_xx + eps_yy) in plane strain and 0 in plane stress.
std::vector<ElementStress> element_stresses(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u);

}  // namespace hemivem
