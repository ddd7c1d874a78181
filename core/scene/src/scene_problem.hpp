// What the scene builders of plane and solid bodies share (private to the scene module): the
// problem on a mesh (scene_problem.cpp) and the words of their messages.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <hemivem/error.hpp>
#include <hemivem/mesh/dimension.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::detail {

/// make(), a generated mesh, its errors named by the scene's `mesh` key: an invalid mesh's
/// MeshError and a generator's InputError.
template <class Make>
auto generated_mesh(const Scene& scene, const Make& make) {
  try {
    return make();
  } catch (const MeshError& e) {
    throw MeshError("mesh: the generated mesh is invalid: " + e.detail(), e.element(), scene.where("mesh"));
  } catch (const InputError& e) {
    throw InputError("mesh: " + e.detail(), scene.where("mesh"));
  }
}

/// A vertex count as an integer when small enough to read, else in scientific notation.
std::string count_text(double v);

/// require_memory() of what the scene's route needs on the mesh `condensed` estimates for the
/// condensed route: `condensed` itself, or the full-space route's (full_space_memory) when
/// solver.linear is a Krylov engine. On the condensed route, when the full-space route would
/// fit, the refusal says so.
void require_route_memory(const Scene& scene, const MemoryEstimate& condensed, const std::string& what,
                          const std::string& where);

/// require_route_memory of the scene's generated mesh (generated_mesh_memory, named by its
/// generator and cells at the scene's mesh.n), before the mesh is made.
void require_generated_memory(const Scene& scene);

/// Every [[material.region]] (those with a box too when `boxes`) names a region some element
/// (cell) of the mesh is in; an error at the region's id otherwise.
template <int dim>
void check_regions_used(const Scene& scene, const MeshOf<dim>& mesh, bool boxes);
/// The same of a mesh whose cells are in the regions `present`.
void check_regions_present(const Scene& scene, const std::set<int>& present, bool boxes);

/// A process's piece of a generated box that holds, of the cells along the box's sides, those
/// of its contact parts alone (scene_piece): on it each support and load picks the facets of the
/// piece's cells that it picks of the whole mesh, which may be none. The processes together
/// (collective over `processes`) then say whether each picks a facet of the whole mesh, and give
/// each support the vertices it holds on the pieces of the others: each process sends those among
/// its own vertices (`owned`, one flag per vertex), every cell around which its piece holds. So
/// too a piece of a mesh file that holds of its boundary the contact's cells alone
/// (MeshPieceRead::picked).
struct SupportsAcross {
  const RowDistribution* processes = nullptr;
  std::vector<char> owned;
};

/// The built problem of `scene` on `mesh` (make_contact_problem), with has_contact and the
/// scene's warnings; the regions checked (check_regions_used) when the mesh is `whole`, not when
/// it is a process's piece, whose regions are checked across the processes
/// (check_regions_of_pieces). `cut`: a piece's boundary facets inside the whole mesh
/// (MeshPieceRead::cut_facets), which no selector picks. `across`: the piece's supports and
/// loads completed across the processes (SupportsAcross; collective), each support's vertices
/// on the others' pieces among its `vertices`.
template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> built_on(const Scene& scene, MeshOf<dim> mesh, bool whole = true,
                                                 std::span<const int> cut = {}, const SupportsAcross* across = nullptr);

/// Puts each element of `mesh` whose centroid lies in a box of the scene's [[material.region]]
/// into that region (the last such box's).
void apply_region_boxes(const Scene& scene, Mesh& mesh);

/// Of a body with region boxes, whose mesh's cells are in the regions `own` before the boxes
/// are applied (a file's, 0 of a generated mesh's): the number of region ids its regions shift
/// the next body's past, one more than the largest of `own` and of its boxes' ids, which every
/// piece of it knows (BodyMesh::regions); 0 without region boxes (its mesh's own).
int region_count(const Scene& one, std::span<const int> own);

/// The problem of a plane scene on `mesh`: the scene's region boxes applied when
/// `apply_region_boxes`, its regions checked when the mesh is `whole`; `cut` and `across` as
/// built_on's.
std::unique_ptr<BuiltProblem> built_plane_on(const Scene& scene, Mesh mesh, bool apply_region_boxes, bool whole,
                                             std::span<const int> cut = {}, const SupportsAcross* across = nullptr);

/// InputError naming the scene's `mesh` key when the scene is not of dimension dim.
template <int dim>
void require_dimension(const Scene& scene);

/// The boundary facets of `mesh` that `selector` picks (sorted, distinct), none of `cut` (as
/// built_on's); an error naming `key` of `scene` when it picks none or names a group the mesh
/// lacks.
template <int dim>
std::vector<int> select_facets(const Scene& scene, const MeshOf<dim>& mesh, const BoundarySelector& selector,
                               const std::string& key, std::span<const int> cut = {});

/// A body's mesh, or a process's piece of it with the piece's boundary facets inside the whole
/// mesh (`cut`, increasing; MeshPieceRead::cut_facets), which no selector picks, and one more
/// than the largest region of the whole (`regions`; 0: the mesh's own), which the piece may lack.
template <int dim>
struct BodyMesh {
  MeshOf<dim> mesh;
  std::vector<int> cut;
  int regions = 0;
};
template <int dim>
using BodyMeshOf = std::function<BodyMesh<dim>(const Scene& one, std::size_t b)>;

/// The meshes `mesh_of(body_scene(scene, b), b)` makes of the bodies b of a scene of several,
/// matched along every contact part against another body (match_interface, match_interface_3d),
/// each with its `cut` facets as the matched mesh numbers them.
template <int dim>
std::vector<BodyMesh<dim>> matched_meshes(const Scene& scene, const BodyMeshOf<dim>& mesh_of);

/// The problem of a scene of several bodies ([[body]], docs/two-bodies.md): each body's mesh
/// made as a scene of one body makes it, the meshes of the bodies that meet matched along each
/// contact part against another body (match_interface), joined into one mesh of several pieces
/// (join_meshes), and each body's materials, supports, loads and contact parts on it; each body's
/// generator's work split among `processes` where it splits it (build_problem).
template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> built_bodies(const Scene& scene, const RowDistribution* processes = nullptr);

/// built_bodies on the meshes `mesh_of(body_scene(scene, b), b)` makes of each body b in place
/// of its whole mesh: a process's piece of each (build_bodies_piece), which holds every facet of
/// the body that a contact part against another body matches; no selector picks its `cut`
/// facets.
template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> built_bodies(const Scene& scene, const BodyMeshOf<dim>& mesh_of);

/// The problem of a plane scene on its own mesh (its generator or file; region boxes applied).
std::unique_ptr<BuiltProblem> built_plane(const Scene& scene, const RowDistribution* processes = nullptr);
/// A plane scene's own mesh, its region boxes not applied: read from its file or generated (its
/// generator's work split among `processes` where it splits it), its memory checked.
Mesh plane_mesh(const Scene& scene, const RowDistribution* processes = nullptr);
/// The problem of a solid scene on its own mesh (its generator or Gmsh file).
std::unique_ptr<BuiltProblem3D> built_solid(const Scene& scene, const RowDistribution* processes = nullptr);
/// The problem of a solid scene on `mesh`: one `given` (build_problem(scene, mesh)) or its Gmsh
/// file's (or a piece of it holding every contact face), its memory checked by its vertices and
/// contact nodes; `cut` and `across` as built_on's.
std::unique_ptr<BuiltProblem3D> built_solid(const Scene& scene, Mesh3D mesh, bool given, std::span<const int> cut = {},
                                            const SupportsAcross* across = nullptr);

/// require_route_memory of a plane scene's mesh file, `condensed` its mesh's estimate
/// (estimate_memory) and `largest` the most vertices of one of its elements.
void require_file_memory(const Scene& scene, const MemoryEstimate& condensed, int largest);

/// The radii and angles (radians) of a plane scene's polar grid (polar_grid of its mesh keys).
std::array<std::vector<double>, 2> polar_lists(const Scene& scene);

/// The polygon of a plane scene's mesh.polygon.
PolygonDomain polygon_domain(const Scene& scene);

}  // namespace hemivem::detail
