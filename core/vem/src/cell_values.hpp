// Each cell of a plane mesh with the values of a displacement at its vertices: what the
// projections of a displacement (project_solution, element_stresses) read.
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/mesh/mesh.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace hemivem::detail {

/// Calls visit(e, polygon, local) for every element e in order: its vertices and the 2n values of
/// u at them. InputError when u has not 2 values per vertex of the mesh.
template <class Visit>
void for_each_cell_values(const Mesh& mesh, const Eigen::VectorXd& u, Visit&& visit) {
  if (u.size() != 2 * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("displacement vector has " + std::to_string(u.size()) + " entries, expected " +
                     std::to_string(2 * mesh.num_vertices()));
  std::vector<Vec2> polygon;
  Eigen::VectorXd local;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto vertices = mesh.element(e);
    polygon.resize(vertices.size());
    local.resize(2 * static_cast<Eigen::Index>(vertices.size()));
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      polygon[i] = mesh.vertex(vertices[i]);
      local.segment<2>(2 * static_cast<Eigen::Index>(i)) = u.segment<2>(2 * static_cast<Eigen::Index>(vertices[i]));
    }
    visit(e, polygon, local);
  }
}

}  // namespace hemivem::detail
