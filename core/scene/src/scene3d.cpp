// A three-dimensional scene made concrete (build_problem_3d), and the peek at a Gmsh file that
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
#include "scene_reader.hpp"

namespace hemivem {

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

// ---- build_problem_3d -------------------------------------------------------------------------

namespace {

std::string point_text(const Vec3& x) { return detail::point_text<3>(x); }

std::string count_text(double v) {
  if (v < 1e9) return std::to_string(static_cast<long long>(std::llround(v)));
  std::ostringstream o;
  o << std::setprecision(2) << std::scientific << v;
  return o.str();
}

/// The scene's mesh: a Gmsh file (its memory checked once its contact faces are known), or a
/// generator whose solve's memory (estimate_memory_3d) is checked before the mesh is made.
Mesh3D scene_mesh_3d(const Scene& scene) {
  const SceneMesh& m = scene.mesh;
  if (!m.file.empty()) return read_gmsh3d(m.file);
  const GridSize3 cells = m.cells3();
  const MemoryEstimate need = estimate_memory_3d(m.generator, cells.nx, cells.ny, cells.nz);
  require_memory(need.solve_bytes,
                 m.generator + " n = " + cells.text() + ": " + count_text(need.vertices) + " vertices",
                 scene.where("mesh.n"));
  const auto& b = m.box;
  try {
    return make_mesh3d(m.generator, cells, Box{b[0], b[1], b[2], b[3], b[4], b[5]}, static_cast<std::uint64_t>(m.seed));
  } catch (const MeshError& e) {
    throw MeshError("mesh: the generated mesh is invalid: " + e.detail(), e.element(), scene.where("mesh"));
  } catch (const InputError& e) {
    throw InputError("mesh: " + e.detail(), scene.where("mesh"));
  }
}

/// The material of each region: the scene's E and nu, but for the regions [[material.region]]
/// names, each of which some cell must be in.
MaterialTable scene_materials_3d(const Scene& scene, const Mesh3D& mesh) {
  const std::set<int> present(mesh.regions().begin(), mesh.regions().end());
  for (std::size_t i = 0; i < scene.material.regions.size(); ++i) {
    const auto& r = scene.material.regions[i];
    if (present.count(r.region)) continue;
    std::string ids;
    for (int id : present) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    const std::string key = "material.region[" + std::to_string(i) + "]";
    throw InputError(key + ".id: region " + std::to_string(r.region) + " matches no cell of the mesh (the mesh's region ids are " +
                         ids + ")",
                     scene.where(scene.lines.count(key + ".id") ? key + ".id" : key));
  }
  int regions = 1;
  for (int r : mesh.regions()) regions = std::max(regions, r + 1);
  for (const auto& r : scene.material.regions) regions = std::max(regions, r.region + 1);
  std::vector<Material> by_region(static_cast<std::size_t>(regions), Material{scene.material.young, scene.material.poisson});
  for (const auto& r : scene.material.regions) by_region[static_cast<std::size_t>(r.region)] = Material{r.young, r.poisson};
  return MaterialTable(by_region, PlaneModel::strain);  // plane strain's Lame constants are the solid's
}

/// The boundary faces a selector of the scene picks (sorted, distinct): the sides of the mesh's
/// bounding box and its face groups; an error naming the selector's key when it picks none or
/// names a group the mesh lacks.
class FaceSelection {
 public:
  FaceSelection(const Scene& scene, const Mesh3D& mesh) : scene_(scene), mesh_(mesh), box_(mesh.bounding_box()) {}

  std::vector<int> operator()(const BoundarySelector& b, const std::string& key) const {
    std::vector<int> faces;
    for (const auto& side : b.sides) {
      const auto f = select_box_side(mesh_, box_, side, b.tolerance);
      faces.insert(faces.end(), f.begin(), f.end());
    }
    for (const auto& g : b.groups) {
      try {
        const auto f = select_boundary_faces(mesh_, g);
        faces.insert(faces.end(), f.begin(), f.end());
      } catch (const InputError& e) {
        throw InputError(key + ".group: " + e.detail(), scene_.where(key + ".group"));
      }
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    if (faces.empty()) throw InputError(key + ": selects no boundary face of the mesh", scene_.where(key));
    return faces;
  }

 private:
  const Scene& scene_;
  const Mesh3D& mesh_;
  const Box box_;
};

void add_dirichlet_3d(ElasticityProblem3D& e, const Scene& scene, const FaceSelection& select) {
  if (!scene.clamped.empty()) e.dirichlet.push_back({select(scene.clamped, "clamped"), {}, {true, true, true}, "clamped"});
  for (std::size_t i = 0; i < scene.dirichlet.size(); ++i) {
    const auto& d = scene.dirichlet[i];
    const std::string key = "dirichlet[" + std::to_string(i) + "]";
    e.dirichlet.push_back({select(d.boundary, key), detail::dirichlet_value_at<3>(scene, i, 1.0),
                           {d.ux.has_value(), d.uy.has_value(), d.uz.has_value()}, key});
  }
}

void add_loads_3d(ElasticityProblem3D& e, const Scene& scene, const FaceSelection& select) {
  e.body_force = detail::body_force_at<3>(scene, 1.0);
  for (std::size_t i = 0; i < scene.tractions.size(); ++i) {
    TractionLoad3D load;
    load.faces = select(scene.tractions[i].boundary, "loads.traction[" + std::to_string(i) + "]");
    detail::set_traction_at<3>(load, scene, i, 1.0);
    e.tractions.push_back(std::move(load));
  }
}

/// A contact part whose every node is clamped leaves nothing to touch: an error.
void check_contact_not_clamped_3d(const ElasticityProblem3D& e, const std::vector<int>& faces, const Mesh3D& mesh,
                                  const Scene& scene, const std::string& key) {
  std::set<int> fixed, touching;
  for (const auto& d : e.dirichlet)
    if (d.fix[0] && d.fix[1] && d.fix[2])
      for (int f : d.faces) fixed.insert(mesh.face(f).vertices.begin(), mesh.face(f).vertices.end());
  for (int f : faces) touching.insert(mesh.face(f).vertices.begin(), mesh.face(f).vertices.end());
  if (std::includes(fixed.begin(), fixed.end(), touching.begin(), touching.end()))
    throw InputError(key + ": every node of the contact part is also clamped ([clamped] or a [[dirichlet]] "
                     "with every component), so nothing is left to touch",
                     scene.where(key));
}

/// The box constraint against an obstacle needs a gap >= 0 at every contact node: an error naming
/// the part's constraint key (the solve checks it too, without the scene). A boundary that
/// cannot be made is left to the solve to report.
void check_box_gaps_3d(const ContactProblem3D& p, const ContactPart3D& part, const Scene& scene, const std::string& key) {
  ContactBoundary boundary;
  try {
    boundary = make_contact_boundary(*p.elasticity.mesh, {part}, make_dof_map(*p.elasticity.mesh, p.elasticity.dirichlet));
  } catch (const InputError&) {
    return;
  }
  const std::string at = scene.lines.count(key + ".constraint") ? key + ".constraint" : key + ".obstacle";
  try {
    for (int i = 0; i < boundary.size(); ++i) require_box_gap(boundary.gaps(i), boundary.nodes[static_cast<std::size_t>(i)]);
  } catch (const InputError& e) {
    throw InputError(at + ": " + e.detail(), scene.where(at));
  }
}

/// Contact part i ([contact] or [[contact]] i): its faces, the obstacle or gap, the law and the
/// constraint.
ContactPart3D make_contact_part_3d(const ContactProblem3D& p, const SceneContact& c, std::size_t i, const Scene& scene,
                                   const Mesh3D& mesh, const FaceSelection& select) {
  const std::string key = contact_key(scene, i);
  ContactPart3D part;
  part.name = contact_part_name(scene, i);
  part.facets = select(c.boundary, key);
  check_contact_not_clamped_3d(p.elasticity, part.facets, mesh, scene, key);
  detail::set_contact_data_at<3>(part, scene, c, i, 1.0);
  try {
    part.law = detail::make_law(c.law);
  } catch (const InputError& err) {
    throw InputError(key + ".law: " + err.detail(), scene.where(key + ".law"));
  }
  part.constraint = c.constraint;
  part.law_from_surface = c.law_origin == "surface";
  if (part.obstacle && part.constraint == ConstraintKind::box) check_box_gaps_3d(p, part, scene, key);
  return part;
}

/// A face in two contact parts: an error at the later part naming both.
void check_parts_disjoint_3d(const std::vector<ContactPart3D>& parts, const Scene& scene, const Mesh3D& mesh) {
  std::map<int, std::size_t> owner;
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (int id : parts[i].facets) {
      const auto [at, added] = owner.emplace(id, i);
      if (added || at->second == i) continue;
      const std::string key = contact_key(scene, i);
      throw InputError(key + ": selects the boundary face at " + point_text(mesh.face_centroid(id)) + ", which " +
                           contact_key(scene, at->second) + " ('" + parts[at->second].name +
                           "') selects too; each face belongs to one contact part (parts may meet at an edge or a "
                           "node, which then belongs to the part listed first)",
                       scene.where(key));
    }
}

void add_contact_3d(ContactProblem3D& p, const Scene& scene, const Mesh3D& mesh, const FaceSelection& select) {
  const std::vector<SceneContact> scene_parts = contact_parts(scene);
  for (std::size_t i = 0; i < scene_parts.size(); ++i)
    p.parts.push_back(make_contact_part_3d(p, scene_parts[i], i, scene, mesh, select));
  check_parts_disjoint_3d(p.parts, scene, mesh);
}

}  // namespace

namespace {

void require_solid_scene(const Scene& scene) {
  if (scene.dimension() != 3)
    throw InputError("mesh: a two-dimensional scene is built by build_problem (build_problem_3d takes a box of six "
                     "numbers, a 3D generator or a Gmsh file of volumes)",
                     scene.where("mesh"));
}

/// The problem of `scene` on `mesh`; `given` when the mesh is not the scene's (its memory is
/// then checked under the scene's mesh key, as a mesh file's is).
std::unique_ptr<BuiltProblem3D> build_on(const Scene& scene, Mesh3D given_mesh, bool given) {
  auto out = std::make_unique<BuiltProblem3D>();
  out->mesh = std::move(given_mesh);
  const Mesh3D& mesh = out->mesh;
  ContactProblem3D& p = out->problem;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = scene_materials_3d(scene, mesh);
  p.elasticity.stabilization = scene.material.stabilization;
  const FaceSelection select(scene, mesh);
  add_dirichlet_3d(p.elasticity, scene, select);
  add_loads_3d(p.elasticity, scene, select);
  add_contact_3d(p, scene, mesh, select);
  if (given || !scene.mesh.file.empty()) {  // a mesh read or given: its vertices and contact nodes counted
    std::set<int> contact;
    for (const ContactPart3D& part : p.parts)
      for (int f : part.facets) contact.insert(mesh.face(f).vertices.begin(), mesh.face(f).vertices.end());
    const MemoryEstimate need = estimate_memory_3d(mesh.num_vertices(), static_cast<double>(contact.size()));
    require_memory(need.solve_bytes,
                   (given ? std::string("the mesh given") : scene.mesh.file.string()) + ": " +
                       count_text(mesh.num_vertices()) + " vertices, " + count_text(static_cast<double>(contact.size())) +
                       " on the contact faces",
                   given ? scene.where("mesh") : scene.where("mesh.file"));
  }
  out->has_contact = scene.contact.has_value();
  out->warnings = scene_warnings(scene);
  return out;
}

}  // namespace

std::unique_ptr<BuiltProblem3D> build_problem_3d(const Scene& scene) {
  require_solid_scene(scene);
  return build_on(scene, scene_mesh_3d(scene), false);
}

std::unique_ptr<BuiltProblem3D> build_problem_3d(const Scene& scene, Mesh3D mesh) {
  require_solid_scene(scene);
  return build_on(scene, std::move(mesh), true);
}

}  // namespace hemivem
