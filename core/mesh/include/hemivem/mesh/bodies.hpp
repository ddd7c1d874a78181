// Several bodies' meshes as one mesh of several pieces.
#pragma once

#include <string>
#include <vector>

#include <hemivem/mesh/mesh.hpp>

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

}  // namespace hemivem
