// What a whole problem's supports, loads and contact parts hold, and the checks of a process's
// piece of it against them (build_problem_piece, cut_problem_piece, read_problem_piece).
#pragma once

#include <hemivem/scene/scene.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

namespace hemivem::test {

/// The facets `edges` (`faces`) of a mesh, each by its sorted vertices.
inline std::set<std::vector<int>> sorted_facets(const Mesh& mesh, const std::vector<int>& edges) {
  std::set<std::vector<int>> out;
  for (int e : edges) out.insert({std::min(mesh.edge(e).v0, mesh.edge(e).v1), std::max(mesh.edge(e).v0, mesh.edge(e).v1)});
  return out;
}
inline std::set<std::vector<int>> sorted_facets(const Mesh3D& mesh, const std::vector<int>& faces) {
  std::set<std::vector<int>> out;
  for (int f : faces) {
    std::vector<int> v = mesh.face(f).vertices;
    std::sort(v.begin(), v.end());
    out.insert(v);
  }
  return out;
}

/// The facets of cell c, each by its sorted vertices: its edges in the plane, its faces in a solid.
inline std::set<std::vector<int>> facets_of_cell(const Mesh& mesh, int e) {
  std::set<std::vector<int>> out;
  const auto polygon = mesh.element(e);
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const int a = polygon[k], b = polygon[(k + 1) % polygon.size()];
    out.insert({std::min(a, b), std::max(a, b)});
  }
  return out;
}
inline std::set<std::vector<int>> facets_of_cell(const Mesh3D& mesh, int c) {
  std::set<std::vector<int>> out;
  for (std::vector<int> loop : mesh.cell(c)) {
    std::sort(loop.begin(), loop.end());
    out.insert(loop);
  }
  return out;
}

/// What a whole problem's supports, loads and contact hold: the facets of the supports and
/// loads (`named`) and of the contact parts, each by its sorted vertices, and the vertices each
/// support holds.
template <int dim>
struct WholeParts {
  std::set<std::vector<int>> named, contact;
  std::vector<std::set<int>> supported;

  explicit WholeParts(const BasicBuiltProblem<dim>& whole) {
    for (const auto& d : whole.problem.elasticity.dirichlet) {
      named.merge(sorted_facets(whole.mesh, d.facets));
      const std::vector<int> held = d.held_vertices(whole.mesh);
      supported.emplace_back(held.begin(), held.end());
    }
    for (const auto& t : whole.problem.elasticity.tractions) named.merge(sorted_facets(whole.mesh, t.facets));
    for (const auto& p : whole.problem.parts) contact.merge(sorted_facets(whole.mesh, p.facets));
  }

  /// Expects of `piece`, whose cells are the cells `cells` of the mesh `whole`: its contact parts
  /// hold the whole's facets; its supports and loads those of `named` among its cells (`among`)
  /// or every one; and (`vertices`) each support every vertex it holds of the whole. Whether it
  /// holds fewer of `named` than the whole.
  bool expect_held_by(const BasicBuiltProblem<dim>& piece, const MeshOf<dim>& whole, const std::set<int>& cells,
                      bool among, bool vertices) const {
    std::set<std::vector<int>> expected;  // the supports' and loads' facets of the piece's cells
    for (const int c : cells)
      for (const auto& f : facets_of_cell(whole, c))
        if (named.count(f)) expected.insert(f);
    if (!among) expected = named;
    std::set<std::vector<int>> held, parts;
    const auto& dirichlet = piece.problem.elasticity.dirichlet;
    EXPECT_EQ(dirichlet.size(), supported.size());
    for (std::size_t k = 0; k < std::min(supported.size(), dirichlet.size()); ++k) {
      held.merge(sorted_facets(piece.mesh, dirichlet[k].facets));
      const std::vector<int> got = dirichlet[k].held_vertices(piece.mesh);
      if (vertices) EXPECT_EQ(std::set<int>(got.begin(), got.end()), supported[k]) << "support " << k << "'s vertices";
    }
    for (const auto& t : piece.problem.elasticity.tractions) held.merge(sorted_facets(piece.mesh, t.facets));
    for (const auto& p : piece.problem.parts) parts.merge(sorted_facets(piece.mesh, p.facets));
    EXPECT_EQ(held, expected);
    EXPECT_EQ(parts, contact);
    return held.size() < named.size();
  }
};

/// Expects a process's piece `piece` of the problem `whole` to see the whole's bodies
/// (piece_bodies: each body's vertices, and its cells in the whole mesh), and the free motions of
/// the piece without supports to be named as those of the whole mesh are, motion by motion
/// (which piece, its cells, box and smallest vertex; the centres and axes of rotations).
template <int dim>
void expect_whole_bodies(const BasicBuiltProblem<dim>& piece, const BasicBuiltProblem<dim>& whole) {
  std::vector<int> cells;
  for (const BodyRange& body : whole.bodies) cells.push_back(body.cells);
  if (whole.bodies.empty()) cells.push_back(whole.mesh.num_cells());
  EXPECT_EQ(piece.problem.elasticity.piece_bodies.first_vertex, body_vertex_starts(whole.bodies, whole.mesh.num_vertices()));
  EXPECT_EQ(piece.problem.elasticity.piece_bodies.cells, cells);
  const BasicRigidMotions<dim> mine(piece.mesh, make_dof_map(piece.mesh, {}), piece.problem.elasticity.piece_bodies);
  const BasicRigidMotions<dim> all(whole.mesh, make_dof_map(whole.mesh, {}));
  ASSERT_EQ(mine.size(), all.size());
  for (int k = 0; k < all.size(); ++k) {
    EXPECT_EQ(mine.describe(k), all.describe(k)) << "free motion " << k;
    EXPECT_EQ(mine.describe_by_axes(k), all.describe_by_axes(k)) << "free motion " << k;
  }
}

}  // namespace hemivem::test
