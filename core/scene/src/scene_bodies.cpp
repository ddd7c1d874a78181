// A scene of several bodies made concrete (docs/two-bodies.md): the bodies' meshes matched along
// their contact and joined into one, each body's data moved onto it.
#include <hemivem/scene/scene.hpp>

#include <algorithm>

#include <hemivem/mesh/bodies.hpp>
#include <hemivem/mesh/interface.hpp>
#include <hemivem/mesh/interface3d.hpp>

#include "scene_problem.hpp"

namespace hemivem::detail {

namespace {

std::size_t body_index(const Scene& scene, const std::string& name) {
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (scene.bodies[b].name == name) return b;
  throw InputError("no body named '" + name + "'");
}

// What differs between the dimensions: how a body's mesh is made, matched and joined.
/// A body's whole mesh, its region boxes applied, and the number of region ids its regions shift
/// the next body's past (region_count of its own regions).
BodyMesh<2> body_mesh(const Scene& one, const RowDistribution* processes) {
  Mesh mesh = plane_mesh(one, processes);
  const int regions = region_count(one, mesh.regions());
  return {build_problem(one, std::move(mesh))->mesh, {}, regions};
}
BodyMesh<3> body_mesh3d(const Scene& one, const RowDistribution* processes) {
  return {built_solid(one, processes)->mesh, {}, 0};
}
MatchedInterface match(const Mesh& a, const std::vector<int>& fa, const Mesh& b, const std::vector<int>& fb, double tol) {
  return match_interface(a, fa, b, fb, tol);
}
MatchedInterface3D match(const Mesh3D& a, const std::vector<int>& fa, const Mesh3D& b, const std::vector<int>& fb,
                         double tol) {
  return match_interface_3d(a, fa, b, fb, tol);
}

/// Facet f's vertices below `below` (those of the mesh before a match added vertices), increasing.
template <class MeshType>
std::vector<int> vertices_below(const MeshType& mesh, int f, int below) {
  std::vector<int> out;
  for (int v : mesh.facet_vertices(f))
    if (v < below) out.push_back(v);
  std::sort(out.begin(), out.end());
  return out;
}

/// `body`'s mesh replaced by `matched` (the same cells, vertices added and interface facets
/// split), its cut facets renumbered: a cut facet lies inside the whole mesh, so matching splits
/// none, and adds at most vertices along an edge of it on the interface (a solid's).
template <int dim>
void rematch(BodyMesh<dim>& body, MeshOf<dim> matched) {
  std::vector<std::vector<int>> keys;
  const int below = body.mesh.num_vertices();
  for (int f : body.cut) keys.push_back(vertices_below(body.mesh, f, below));
  std::sort(keys.begin(), keys.end());
  body.mesh = std::move(matched);
  body.cut.clear();
  if (keys.empty()) return;
  for (int f : body.mesh.boundary_facets())
    if (std::binary_search(keys.begin(), keys.end(), vertices_below(body.mesh, f, below))) body.cut.push_back(f);
  std::sort(body.cut.begin(), body.cut.end());
  if (body.cut.size() != keys.size()) throw InternalError("matching a piece of a body's mesh lost a facet where it meets the others");
}

}  // namespace

template <int dim>
std::vector<BodyMesh<dim>> matched_meshes(const Scene& scene, const BodyMeshOf<dim>& mesh_of) {
  std::vector<BodyMesh<dim>> meshes;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) meshes.push_back(mesh_of(body_scene(scene, b), b));
  const std::vector<SceneContact> parts = contact_parts(scene);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const SceneContact& c = parts[k];
    if (!c.against || c.pairing == BodyPairing::projection) continue;  // projected: the meshes stay as they are
    const std::size_t a = body_index(scene, c.body), b = body_index(scene, c.against_body);
    const std::string key = contact_key(scene, k);
    const std::vector<int> side = select_facets<dim>(scene, meshes[a].mesh, c.boundary, key, meshes[a].cut);
    const std::vector<int> other = select_facets<dim>(scene, meshes[b].mesh, *c.against, key + ".against", meshes[b].cut);
    try {
      auto m = match(meshes[a].mesh, side, meshes[b].mesh, other, std::max(c.boundary.tolerance, 1e-8));
      rematch(meshes[a], std::move(m.first));
      rematch(meshes[b], std::move(m.second));
    } catch (const InputError& e) {
      throw InputError(key + ": body '" + c.body + "' and body '" + c.against_body +
                           "' do not meet along this part: " + e.detail(),
                       scene.where(key));
    }
  }
  return meshes;
}

template std::vector<BodyMesh<2>> matched_meshes<2>(const Scene&, const BodyMeshOf<2>&);
template std::vector<BodyMesh<3>> matched_meshes<3>(const Scene&, const BodyMeshOf<3>&);

namespace {

/// Body b's materials, supports and loads on the joined mesh.
template <int dim>
void add_body(const Scene& scene, std::size_t b, const BasicBuiltProblem<dim>& body, const BasicJoinedMeshes<dim>& joined,
              BasicContactProblem<dim>& into, std::vector<Material>& by_region) {
  const auto& e = body.problem.elasticity;
  const std::vector<int>& edge_of = joined.facet_of[b];
  int largest = 0;
  for (int r : body.mesh.regions()) largest = std::max(largest, r);
  for (int r = 0; r <= largest; ++r) {
    const auto at = static_cast<std::size_t>(joined.first_region[b] + r);
    if (by_region.size() <= at) by_region.resize(at + 1);
    by_region[at] = e.materials.material(r);
  }
  const std::string& name = scene.bodies[b].name;
  for (auto d : e.dirichlet) {
    for (int& f : d.facets) f = edge_of[static_cast<std::size_t>(f)];
    for (int& v : d.vertices) v += joined.first_vertex[b];
    d.name = name + "." + d.name;
    into.elasticity.dirichlet.push_back(std::move(d));
  }
  for (auto t : e.tractions) {
    for (int& f : t.facets) f = edge_of[static_cast<std::size_t>(f)];
    into.elasticity.tractions.push_back(std::move(t));
  }
}

/// The plane model, the stabilization and the body force are one for all bodies.
void require_shared(const Scene& scene) {
  const SceneBody& first = scene.bodies.front();
  for (std::size_t b = 1; b < scene.bodies.size(); ++b) {
    const SceneBody& other = scene.bodies[b];
    const std::string key = "body[" + std::to_string(b) + "]";
    if (other.material.model != first.material.model || other.material.stabilization != first.material.stabilization)
      throw InputError(key + ".material: the bodies of a scene share one plane model and one stabilization",
                       scene.where(key + ".material"));
    if (other.body_force != first.body_force)
      throw InputError(key + ".loads.body_force: the bodies of a scene share one body force", scene.where(key + ".loads"));
  }
}

}  // namespace

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> built_bodies(const Scene& scene, const RowDistribution* processes) {
  return built_bodies<dim>(scene, [processes](const Scene& one, std::size_t) {
    if constexpr (dim == 2) return body_mesh(one, processes);
    else return body_mesh3d(one, processes);
  });
}

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> built_bodies(const Scene& scene, const BodyMeshOf<dim>& mesh_of) {
  require_shared(scene);
  std::vector<BodyMesh<dim>> meshes = matched_meshes<dim>(scene, mesh_of);
  std::vector<std::unique_ptr<BasicBuiltProblem<dim>>> bodies;
  std::vector<const MeshOf<dim>*> pieces;
  std::vector<std::string> names;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    bodies.push_back(built_on<dim>(body_scene(scene, b), std::move(meshes[b].mesh), true, meshes[b].cut));
    pieces.push_back(&bodies.back()->mesh);
    names.push_back(scene.bodies[b].name);
  }
  std::vector<int> region_counts;
  for (const BodyMesh<dim>& m : meshes) region_counts.push_back(m.regions);
  auto joined = join_meshes(pieces, names, region_counts);
  auto out = std::make_unique<BasicBuiltProblem<dim>>();
  out->mesh = std::move(joined.mesh);
  BasicContactProblem<dim>& p = out->problem;
  p.elasticity.mesh = &out->mesh;
  p.elasticity.stabilization = bodies.front()->problem.elasticity.stabilization;
  p.elasticity.body_force = bodies.front()->problem.elasticity.body_force;
  std::vector<Material> by_region;
  for (std::size_t b = 0; b < bodies.size(); ++b) add_body(scene, b, *bodies[b], joined, p, by_region);
  p.elasticity.materials = MaterialTable(by_region, bodies.front()->problem.elasticity.materials.model());
  // the contact parts, in the scene's order, each from its body's problem
  const std::vector<SceneContact> parts = contact_parts(scene);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::size_t a = body_index(scene, parts[k].body);
    const std::string name = contact_part_name(scene, k);
    const auto& own = bodies[a]->problem.parts;
    auto part = *std::find_if(own.begin(), own.end(), [&](const auto& x) { return x.name == name; });
    for (int& f : part.facets) f = joined.facet_of[a][static_cast<std::size_t>(f)];
    if (parts[k].against) {
      part.pairing = parts[k].pairing;
      const std::size_t b = body_index(scene, parts[k].against_body);
      for (int f : select_facets<dim>(scene, bodies[b]->mesh, *parts[k].against, contact_key(scene, k) + ".against",
                                      meshes[b].cut))
        part.against.push_back(joined.facet_of[b][static_cast<std::size_t>(f)]);
    }
    p.parts.push_back(std::move(part));
  }
  for (std::size_t b = 0; b < bodies.size(); ++b)
    out->bodies.push_back({scene.bodies[b].name, joined.first_vertex[b], bodies[b]->mesh.num_vertices(),
                           joined.first_cell[b], bodies[b]->mesh.num_cells(), joined.first_region[b]});
  out->has_contact = !p.parts.empty();
  out->warnings = scene_warnings(scene);
  return out;
}

template std::unique_ptr<BuiltProblem> built_bodies<2>(const Scene&, const RowDistribution*);
template std::unique_ptr<BuiltProblem3D> built_bodies<3>(const Scene&, const RowDistribution*);
template std::unique_ptr<BuiltProblem> built_bodies<2>(const Scene&, const BodyMeshOf<2>&);
template std::unique_ptr<BuiltProblem3D> built_bodies<3>(const Scene&, const BodyMeshOf<3>&);

}  // namespace hemivem::detail
