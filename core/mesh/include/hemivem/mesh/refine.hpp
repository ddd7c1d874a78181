// Adaptive refinement of polygonal meshes (docs/reference/meshes.md, "Refinement").
//
// An element is split around an interior point into one quadrilateral per corner: each of its
// geometric sides is cut at its midpoint and the point is joined to every midpoint. A midpoint
// that lands inside an edge of an element that is not split becomes one more vertex of that
// element's polygon (a hanging node: the mesh stays conforming, as the virtual element method
// allows any polygon), and at most one such vertex per side is allowed: neighbours that would
// carry more are split too. Regions, edge groups and the boundary follow the refinement, and a
// prolongation matrix interpolates nodal values from the parent mesh onto the refined one.
//
// Every tolerance is relative to an element's size: the same mesh at any scale is refined the
// same way. The same input always gives the same numbering.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <span>
#include <vector>

#include <hemivem/mesh/mesh.hpp>

namespace hemivem {

/// A mesh refined from a parent mesh, and how each of its parts came from the parent.
struct RefinedMesh {
  /// The refined mesh. Vertex i < parent.num_vertices() is parent vertex i (same position);
  /// new vertices follow, made while walking the split elements in increasing id: for each,
  /// the midpoints of its sides not made before, then its interior point. Elements follow the
  /// parent's order: an element that is not split keeps its place (with any midpoints of its
  /// neighbours added to its polygon), a split element is replaced by its children, one per
  /// corner, in the order of its corners. Regions and edge groups are inherited.
  Mesh mesh;
  /// Per element of `mesh`: the element of the parent mesh it lies in.
  std::vector<int> parent_element;
  /// Per edge of `mesh`: the parent edge it is part of (the whole edge or a piece of it), or -1
  /// for an edge inside a split parent element (from its interior point to a side midpoint).
  std::vector<int> parent_edge;
  /// Per vertex of `mesh`, its value as a combination of the parent's vertex values
  /// (num_vertices() x parent.num_vertices(), rows summing to 1): an old vertex keeps its value,
  /// an edge midpoint is the mean of the edge's ends (exact: VEM functions are linear on edges;
  /// a point cut elsewhere on an edge, which a side made of several edges can need, takes the
  /// linear interpolation of the edge's ends), an interior point of a split element takes the
  /// element's mean value coordinates (exact for linear fields). Apply per component to
  /// interpolate a displacement (see prolongate).
  Eigen::SparseMatrix<double, Eigen::RowMajor> prolongation;
  /// The parent elements that were split, sorted: the marked ones and those the
  /// one-hanging-node rule added.
  std::vector<int> refined;
};

/// The corners of element e of a mesh: the local indices (positions in mesh.element(e), in
/// increasing order) of its vertices that are not hanging. A vertex is hanging in an element
/// when it lies strictly between its two neighbours in that element's polygon, at a distance
/// from the segment joining them of at most 1e-10 of the element's diameter; hanging vertices
/// are taken out one at a time, the nearest to that segment first, a vertex's neighbours being
/// those left after the earlier ones were taken out (so of two vertices a round-off apart at a
/// corner, as at the edges of nearly zero length of Sutton's Voronoi meshes, one stays a
/// corner). At least 3 corners remain. The element's geometric sides run from one corner to
/// the next. A square whose neighbour was split has 5 vertices and 4 corners. Throws
/// InputError for e out of range.
std::vector<int> element_corners(const Mesh& mesh, int e);

/// Splits the marked elements (ids into mesh; duplicates allowed; InputError for an id out of
/// range) and every element the one-hanging-node rule adds.
///
/// The split: each geometric side of the element (see element_corners) is cut at the midpoint
/// of its end corners; a vertex already there (within 1e-8 of the side's length: the hanging
/// node of an earlier split) is reused, else a new vertex is made on the edge that holds the
/// midpoint and shared with the element across that edge. An interior point c is joined to every
/// side midpoint; the children are one quadrilateral per corner (corner, the vertices along the
/// side up to its midpoint, c, the previous side's midpoint and the vertices after it), which
/// may carry hanging nodes. c is the element's centroid when that lies strictly inside the kernel of
/// the polygon of its geometric sides (at a distance of more than 1e-8 of the diameter from
/// every side's line), else the centroid of the kernel (the polygon clipped by each side's inner
/// half-plane). An element whose kernel is empty or degenerate throws InputError naming it
/// ("element 17 is not star-shaped: ..."), as does an element added by the rule.
///
/// The one-hanging-node rule: an element that is not marked, but one of whose sides would
/// receive a new midpoint from a split neighbour and then carry more than one vertex strictly
/// inside it (its existing hanging vertices and the new midpoints counted), is marked too, up
/// to a fixed point. On a mesh whose sides carry at most one vertex each, at their midpoints
/// (every generated mesh and every mesh refine_mesh makes from one), the refined mesh keeps
/// that property, so no element has more than twice as many vertices as corners.
///
/// Children inherit the region of their parent; each piece of a split edge belongs to the
/// edge groups of the edge, so a group covers the same segments as before; boundary edges
/// stay on the boundary and the bounding box does not change. The cost is linear in the size
/// of the mesh. A refined element that would not be a valid polygon (see find_mesh_defects)
/// throws MeshError naming the parent element.
RefinedMesh refine_mesh(const Mesh& mesh, std::span<const int> marked);

/// Every element split once (refine_mesh with every element marked).
RefinedMesh refine_uniformly(const Mesh& mesh);

/// Dörfler (bulk) marking: the smallest set of elements, taken in decreasing order of eta_E,
/// whose eta_E^2 sum to at least theta * sum eta_E^2 (theta in (0, 1]; InputError otherwise),
/// with every element tied with the last one taken: an eta_E within 1e-6 of the largest of it.
/// Cells that are mirror images of each other (a symmetric problem) have indicators equal to
/// round-off, and one is not marked without the other: the marking, and so the adaptive meshes,
/// do not depend on the round-off of the solution (its engine, its number of processes). The
/// result is deterministic. theta = 1 marks every element
/// with eta_E > 0; indicators that are all zero mark none. Throws InputError for a negative or
/// non-finite eta_E. The sums are scaled by the largest eta_E, so any finite indicators work.
/// Returns element ids sorted ascending.
std::vector<int> dorfler_marking(std::span<const double> eta, double theta);

/// Interpolates a nodal vector with 2 entries per vertex (x, y interleaved) of the parent mesh
/// onto the refined mesh (refined.prolongation applied to each component). Throws InputError
/// when parent_values does not have 2 entries per parent vertex.
Eigen::VectorXd prolongate(const RefinedMesh& refined, const Eigen::VectorXd& parent_values);

}  // namespace hemivem
