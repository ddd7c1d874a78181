// result.json's "bodies" of a scene of several bodies (docs/reference/outputs.md).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app::detail {

/// The load applied to each body of `bodies` (ranges of problem's mesh): the sum of the load
/// vector over its vertices, `dim` values per body; with `vertices` (a mask of the mesh's
/// vertices) over those only: on a process's piece of the mesh, its share of the vertices, at
/// which the piece's load vector is the whole mesh's.
template <int dim>
std::vector<double> body_loads(const BasicContactProblem<dim>& problem, const std::vector<BodyRange>& bodies,
                               const std::vector<char>* vertices = nullptr);

/// Per body: its name, its vertices and cells in the mesh (first and count), and the balance of
/// the forces on it: the load applied to it (`applied`, body_loads), the reactions of its
/// supports (the Dirichlet parts named "body.part"), the contact forces on it (of its own
/// contact nodes, and the opposite of those of the nodes paired with its vertices) and the
/// relative residual of their sum. Null for one body.
template <int dim>
nlohmann::json bodies_json(const std::vector<double>& applied, const BasicContactSolution<dim>& s,
                           const std::vector<BodyRange>& bodies);

}  // namespace hemivem::app::detail
