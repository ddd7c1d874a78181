// The linear elasticity problem of a plane (dim = 2) or a solid (dim = 3) body: its mesh,
// materials, loads and prescribed displacements (Gamma_1), written once for both dimensions.
// Facets are boundary edges (2D) or boundary faces (3D).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <hemivem/mesh/body_range.hpp>
#include <hemivem/mesh/dimension.hpp>
#include <hemivem/vem/element.hpp>
#include <hemivem/vem/material.hpp>

namespace hemivem {

using VectorField = VectorFieldOf<2>;
using VectorField3 = VectorFieldOf<3>;

/// Prescribed displacement on the vertices of a set of boundary facets and on single vertices
/// (a pinned node, a point support). `value` empty means clamped (zero). `fix` selects the
/// components that are prescribed.
template <int dim>
struct BasicDirichletCondition {
  std::vector<int> facets;  ///< boundary edge (2D) or face (3D) ids
  VectorFieldOf<dim> value;
  std::array<bool, dim> fix = all_components();
  std::string name;  ///< how the problem names the part (e.g. a scene's "clamped"); may be empty
  std::vector<int> vertices;  ///< single vertex ids held besides the facets' vertices

  /// Every vertex the condition holds: its facets' vertices, then `vertices` (a vertex may
  /// repeat). InputError naming the facet or vertex id that `mesh` lacks.
  std::vector<int> held_vertices(const MeshOf<dim>& mesh) const;

  static constexpr std::array<bool, dim> all_components() {
    std::array<bool, dim> all{};
    all.fill(true);
    return all;
  }
};

/// A surface traction on a set of boundary facets: `traction`, plus -p n for a `pressure` p
/// (n the facet's outward unit normal: a positive pressure pushes into the body); at least
/// one of the two is given. On an edge it is integrated with a 3-point Gauss rule against the
/// linear hat functions; on a face, against the face's projection onto linear functions (the
/// enhanced face space), with a degree-5 rule on the fan of triangles from the face centroid.
/// Both are exact for tractions of degree <= 4 on each facet.
template <int dim>
struct BasicTractionLoad {
  std::vector<int> facets;  ///< boundary edge (2D) or face (3D) ids
  VectorFieldOf<dim> traction;
  std::function<double(const PointOf<dim>&)> pressure;
};

/// The linear elasticity problem on a mesh. In 3D the materials' Lame constants are the
/// three-dimensional ones (MaterialTable::lame of plane strain), and the body force is
/// integrated against Pi^nabla_1 phi with a degree-2 rule on a fan of tetrahedra.
template <int dim>
struct BasicElasticityProblem {
  const MeshOf<dim>* mesh = nullptr;
  MaterialTable materials;
  Stabilization stabilization = Stabilization::two_mu;
  VectorFieldOf<dim> body_force;  ///< f0; empty = none
  std::vector<BasicTractionLoad<dim>> tractions;
  std::vector<BasicDirichletCondition<dim>> dirichlet;
  /// Empty, or `mesh` is a process's piece of a mesh whose connected bodies are those of
  /// piece_bodies ({{0, the number of vertices}, {the whole mesh's cells}} for one body;
  /// hemivem/scene/scene_pieces.hpp), which holds every vertex of the whole mesh and of the cells
  /// only some, each body's in one piece: its vertices of no cell lie on their body too, and its
  /// supports may hold them (BasicDirichletCondition::vertices), so the rigid motions the
  /// supports leave free are judged, and named, of the whole bodies (BasicRigidMotions).
  PieceBodies piece_bodies;
};

using DirichletCondition = BasicDirichletCondition<2>;
using TractionLoad = BasicTractionLoad<2>;
using ElasticityProblem = BasicElasticityProblem<2>;
using DirichletCondition3D = BasicDirichletCondition<3>;
using TractionLoad3D = BasicTractionLoad<3>;
using ElasticityProblem3D = BasicElasticityProblem<3>;

}  // namespace hemivem
