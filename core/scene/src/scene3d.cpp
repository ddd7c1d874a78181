// A three-dimensional scene made concrete (build_problem<3>), and the peek at a Gmsh file that
// tells a solid's mesh (mesh_files3d.hpp).
#include <hemivem/scene/mesh_files3d.hpp>
#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/contact/supports.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/scene/resources.hpp>

#include "scene_fields.hpp"
#include "scene_problem.hpp"
#include "scene_reader.hpp"

namespace hemivem {

using detail::count_text;
using detail::fmt;
using detail::lower;

namespace detail {

Obstacle3D make_obstacle3d(const SceneObstacle& o) {
  Obstacle3D b;
  b.shape = obstacle3d_shape_from_string(o.shape);
  b.point = Vec3(o.point[0], o.point[1], o.point[2]);
  b.normal = Vec3(o.normal[0], o.normal[1], o.normal[2]);
  b.center = Vec3(o.center[0], o.center[1], o.center[2]);
  b.axis = Vec3(o.axis[0], o.axis[1], o.axis[2]);
  b.radius = o.radius;
  return b;
}

}  // namespace detail

// ---- Gmsh files of solids ---------------------------------------------------------------------

int gmsh_file_dimension(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return 2;  // never a device or a pipe
  std::ifstream in(path);
  if (!in) return 2;
  std::string line;
  auto next = [&]() -> bool {
    if (!std::getline(in, line)) return false;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  while (next()) {
    if (line != "$Elements") continue;
    // numEntityBlocks numElements minElementTag maxElementTag, then per block
    // "entityDim entityTag elementType numElementsInBlock" and its element lines
    if (!next()) return 2;
    long long blocks = 0;
    if (!(std::istringstream(line) >> blocks) || blocks < 0) return 2;
    for (long long b = 0; b < blocks; ++b) {
      if (!next()) return 2;
      long long dim = -1, tag = 0, type = 0, count = -1;
      if (!(std::istringstream(line) >> dim >> tag >> type >> count) || count < 0) return 2;
      if (dim == 3) return 3;
      for (long long k = 0; k < count; ++k)
        if (!next()) return 2;
    }
    return 2;
  }
  return 2;
}

// ---- the problem of a solid -------------------------------------------------------------------------

namespace {

/// The scene's mesh: a Gmsh file (its memory checked once its contact faces are known), or a
/// generator whose solve's memory (estimate_memory_3d) is checked before the mesh is made, its
/// work split among `processes` where it splits it (make_mesh3d).
Mesh3D scene_mesh_3d(const Scene& scene, const RowDistribution* processes) {
  const SceneMesh& m = scene.mesh;
  if (!m.file.empty()) return read_gmsh3d(m.file);
  detail::require_generated_memory(scene);
  const auto& b = m.box;
  return detail::generated_mesh(scene, [&] {
    return make_mesh3d(m.generator, m.cells3(), Box{b[0], b[1], b[2], b[3], b[4], b[5]}, static_cast<std::uint64_t>(m.seed),
                       processes);
  });
}

}  // namespace

namespace detail {

std::unique_ptr<BuiltProblem3D> built_solid(const Scene& scene, Mesh3D mesh, bool given, std::span<const int> cut,
                                            const SupportsAcross* across) {
  auto out = detail::built_on<3>(scene, std::move(mesh), true, cut, across);
  if (given || !scene.mesh.file.empty()) {  // a mesh read or given: its vertices and contact nodes counted
    const Mesh3D& m = out->mesh;
    std::set<int> contact;
    for (const ContactPart3D& part : out->problem.parts)
      for (int f : part.facets) contact.insert(m.face(f).vertices.begin(), m.face(f).vertices.end());
    const MemoryEstimate condensed = estimate_memory_3d(m.num_vertices(), static_cast<double>(contact.size()));
    const std::string what = (given ? std::string("the mesh given") : scene.mesh.file.string()) + ": " +
                             count_text(m.num_vertices()) + " vertices, " +
                             count_text(static_cast<double>(contact.size())) + " on the contact faces";
    detail::require_route_memory(scene, condensed, what, given ? scene.where("mesh") : scene.where("mesh.file"));
  }
  return out;
}

std::unique_ptr<BuiltProblem3D> built_solid(const Scene& scene, const RowDistribution* processes) {
  return built_solid(scene, scene_mesh_3d(scene, processes), false);
}

}  // namespace detail

std::unique_ptr<BuiltProblem3D> build_problem(const Scene& scene, Mesh3D mesh) {
  detail::require_dimension<3>(scene);
  return detail::built_solid(scene, std::move(mesh), true);
}

}  // namespace hemivem
