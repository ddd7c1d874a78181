// The balance of forces (hemivem/contact/forces.hpp) of some vertices alone, which the processes
// of the full-space route across processes add up, each over its own vertices.
#pragma once

#include <hemivem/contact/forces.hpp>

#include <utility>
#include <vector>

namespace hemivem::detail {

/// force_balance(problem, u, contact, at_vertices) with the load, the reactions and the forces
/// at vertices of the vertices `vertices` (increasing) alone, summed in their order; `contact` as
/// given. Exact on a mesh holding every cell of those vertices (a process's piece,
/// hemivem/mesh/box_piece.hpp): the balances of a split of the vertices add up to the whole's.
template <int dim>
BasicForceBalance<PointOf<dim>> force_balance_of_vertices(const BasicElasticityProblem<dim>& problem,
                                                          const Eigen::VectorXd& u, const PointOf<dim>& contact,
                                                          const std::vector<std::pair<int, PointOf<dim>>>& at_vertices,
                                                          const std::vector<int>& vertices);

}  // namespace hemivem::detail
