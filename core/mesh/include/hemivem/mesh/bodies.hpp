// Several bodies' meshes as one mesh of several pieces.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// The bodies' meshes joined into one (join_meshes), and where each body's parts went.
struct JoinedMeshes {
  /// The pieces: body b's vertices, elements and regions follow those of the bodies before it.
  Mesh mesh;
  std::vector<int> first_vertex;  ///< per body: its vertex 0 in `mesh` (then consecutively)
  std::vector<int> first_element; ///< per body: its element 0 in `mesh`
  std::vector<int> first_region;  ///< per body: the region its region 0 becomes (regions shift, never merge)
  /// Per body, per edge of its mesh: the edge of `mesh` it is.
  std::vector<std::vector<int>> edge_of;
};

/// One mesh of the bodies `bodies` (in order) that share nothing: vertices, elements and
/// regions are renumbered by offsets (a body's regions shift past the largest region of the
/// bodies before it), and each body's edge groups are kept under "name.group" (the body's name
/// from `names`). The bodies may touch or overlap; they stay separate pieces (no vertex is
/// merged). InputError for an empty list or a names list of another length or with an empty or
/// repeated name.
JoinedMeshes join_meshes(const std::vector<const Mesh*>& bodies, const std::vector<std::string>& names);

/// Several solids' meshes joined into one (join_meshes), and where each body's parts went.
struct JoinedMeshes3D {
  /// The pieces: body b's vertices, cells and regions follow those of the bodies before it.
  Mesh3D mesh;
  std::vector<int> first_vertex;  ///< per body: its vertex 0 in `mesh` (then consecutively)
  std::vector<int> first_cell;    ///< per body: its cell 0 in `mesh`
  std::vector<int> first_region;  ///< per body: the region its region 0 becomes (regions shift, never merge)
  /// Per body, per face of its mesh: the face of `mesh` it is.
  std::vector<std::vector<int>> face_of;
};

/// One mesh of the solids `bodies` (in order) that share nothing: vertices, cells and regions
/// are renumbered by offsets (a body's regions shift past the largest region of the bodies
/// before it), and each body's face groups are kept under "name.group" (the body's name from
/// `names`). The bodies may touch or overlap; they stay separate pieces (no vertex is merged):
/// a face of one body at the place of a face of another has other vertex ids, so the two stay
/// two boundary faces, one per body. InputError for an empty list or a names list of another
/// length or with an empty or repeated name.
JoinedMeshes3D join_meshes(const std::vector<const Mesh3D*>& bodies, const std::vector<std::string>& names);

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
