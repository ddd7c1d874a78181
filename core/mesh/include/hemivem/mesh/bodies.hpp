// Several bodies' meshes as one mesh of several pieces.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include <hemivem/mesh/dimension.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// The bodies' meshes joined into one (join_meshes), plane (dim = 2) or solid (dim = 3), and
/// where each body's parts went.
template <int dim>
struct BasicJoinedMeshes {
  /// The pieces: body b's vertices, cells and regions follow those of the bodies before it.
  MeshOf<dim> mesh;
  std::vector<int> first_vertex;  ///< per body: its vertex 0 in `mesh` (then consecutively)
  std::vector<int> first_cell;    ///< per body: its cell 0 in `mesh`
  std::vector<int> first_region;  ///< per body: the region its region 0 becomes (regions shift, never merge)
  /// Per body, per facet (edge, face) of its mesh: the facet of `mesh` it is.
  std::vector<std::vector<int>> facet_of;
};
using JoinedMeshes = BasicJoinedMeshes<2>;
using JoinedMeshes3D = BasicJoinedMeshes<3>;

/// One mesh of the bodies `bodies` (in order) that share nothing: vertices, cells and regions
/// are renumbered by offsets (a body's regions shift past the largest region of the bodies
/// before it), and each body's edge (face) groups are kept under "name.group" (the body's name
/// from `names`). The bodies may touch or overlap; they stay separate pieces (no vertex is
/// merged): a plane mesh is told which body each vertex is in (Mesh's `bodies`), and a face of
/// one solid at the place of a face of another has other vertex ids, so the two stay two
/// boundary faces. `region_counts`, when given, is per body the number of region ids its
/// regions shift the next body's past at least (one more than the largest region of the body's
/// whole mesh, of which `bodies` may be pieces that lack some). InputError for an empty list or
/// a names list of another length or with an empty or repeated name, or region counts of
/// another length.
JoinedMeshes join_meshes(const std::vector<const Mesh*>& bodies, const std::vector<std::string>& names,
                         const std::vector<int>& region_counts = {});
JoinedMeshes3D join_meshes(const std::vector<const Mesh3D*>& bodies, const std::vector<std::string>& names,
                           const std::vector<int>& region_counts = {});

/// join_meshes of a braced list of bodies, `join_meshes({&a, &b}, names)`: without these the
/// list of two pointers could make either vector (by its constructor from two iterators) and
/// the call would be ambiguous between the plane's and the solid's join_meshes.
inline JoinedMeshes join_meshes(std::initializer_list<const Mesh*> bodies, const std::vector<std::string>& names) {
  return join_meshes(std::vector<const Mesh*>(bodies), names);
}
inline JoinedMeshes3D join_meshes(std::initializer_list<const Mesh3D*> bodies, const std::vector<std::string>& names) {
  return join_meshes(std::vector<const Mesh3D*>(bodies), names);
}

}  // namespace hemivem
