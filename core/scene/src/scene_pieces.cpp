// A scene's mesh made in pieces across processes (hemivem/scene/scene_pieces.hpp).
#include <hemivem/scene/scene_pieces.hpp>

#include <hemivem/contact/pose_share.hpp>
#include <hemivem/error.hpp>

#include "scene_problem.hpp"

#include <algorithm>
#include <limits>
#include <tuple>
#include <string>
#include <vector>

namespace hemivem {

namespace {

/// Adds the sides of `b` to `sides`; false when `b` selects by anything else.
bool add_sides(const BoundarySelector& b, std::vector<std::string>& sides) {
  if (!b.groups.empty() || !b.segments.empty() || !b.points.empty()) return false;
  sides.insert(sides.end(), b.sides.begin(), b.sides.end());
  return true;
}

/// The vertices of the scene's generated mesh.
long long scene_vertices(const Scene& scene) {
  if (scene.dimension() == 3) {
    const GridSize3 n = scene.mesh.cells3();
    return static_cast<long long>(n.nx + 1) * (n.ny + 1) * (n.nz + 1);
  }
  const GridSize n = scene.mesh.cells();
  return static_cast<long long>(n.nx + 1) * (n.ny + 1);
}

}  // namespace

std::optional<BoxPiece> scene_piece(const Scene& scene, int rank, int size) {
  const SceneMesh& m = scene.mesh;
  if (!scene.bodies.empty() || !m.file.empty() || !makes_pieces(m.generator) || !m.polygon.empty() || scene.adapt)
    return std::nullopt;
  if (std::any_of(scene.material.regions.begin(), scene.material.regions.end(), [](const auto& r) { return r.box.has_value(); }))
    return std::nullopt;
  BoxPiece piece;
  bool sides_only = add_sides(scene.clamped, piece.sides);
  for (const SceneDirichlet& d : scene.dirichlet) sides_only = add_sides(d.boundary, piece.sides) && sides_only;
  for (const SceneTraction& t : scene.tractions) sides_only = add_sides(t.boundary, piece.sides) && sides_only;
  for (const SceneContact& c : contact_parts(scene)) sides_only = add_sides(c.boundary, piece.sides) && sides_only;
  if (!sides_only) return std::nullopt;
  std::sort(piece.sides.begin(), piece.sides.end());
  piece.sides.erase(std::unique(piece.sides.begin(), piece.sides.end()), piece.sides.end());
  const long long vertices = scene_vertices(scene);
  if (vertices > std::numeric_limits<int>::max()) return std::nullopt;
  std::tie(piece.first_vertex, piece.end_vertex) = vertex_share(static_cast<int>(vertices), rank, size);
  return piece;
}

PieceOfMesh scene_piece_of_mesh(const Scene& scene, const BoxPiece& piece) {
  PieceOfMesh out;
  out.first_vertex = piece.first_vertex;
  out.end_vertex = piece.end_vertex;
  const std::string& g = scene.mesh.generator;
  if (scene.dimension() == 3) {
    const GridSize3 n = scene.mesh.cells3();
    out.cells = piece_cells(g, n, piece);
    out.whole_cells = n.nx * n.ny * n.nz * cells_per_box(g);
  } else {
    const GridSize n = scene.mesh.cells();
    out.cells = piece_cells(g, n, piece);
    out.whole_cells = n.nx * n.ny * cells_per_box(g);
  }
  return out;
}

template <>
std::unique_ptr<BasicBuiltProblem<2>> build_problem_piece<2>(const Scene& scene, const BoxPiece& piece) {
  const auto& d = scene.mesh.domain;
  Mesh mesh = detail::generated_mesh(scene, [&] {
    return make_mesh_piece(scene.mesh.generator, scene.mesh.cells(), Rectangle{d[0], d[1], d[2], d[3]}, piece);
  });
  return build_problem(scene, std::move(mesh), false);
}

template <>
std::unique_ptr<BasicBuiltProblem<3>> build_problem_piece<3>(const Scene& scene, const BoxPiece& piece) {
  const auto& b = scene.mesh.box;
  Mesh3D mesh = detail::generated_mesh(scene, [&] {
    return make_mesh3d_piece(scene.mesh.generator, scene.mesh.cells3(), Box{b[0], b[1], b[2], b[3], b[4], b[5]}, piece);
  });
  return build_problem(scene, std::move(mesh));
}

}  // namespace hemivem
