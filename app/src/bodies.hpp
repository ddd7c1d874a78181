// result.json's "bodies" of a scene of several bodies (docs/reference/outputs.md).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app::detail {

/// Per body: its name, its vertices and cells in the mesh (first and count), and the balance of
/// the forces on it: the load applied to it, the reactions of its supports (the Dirichlet parts
/// named "body.part"), the contact forces on it (of its own contact nodes, and the opposite of
/// those of the nodes paired with its vertices) and the relative residual of their sum. Null
/// for one body.
template <int dim>
nlohmann::json bodies_json(const BasicContactProblem<dim>& problem, const BasicContactSolution<dim>& s,
                           const std::vector<BodyRange>& bodies);

}  // namespace hemivem::app::detail
