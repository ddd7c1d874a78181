// Adaptive refinement of polyhedral meshes (docs/reference/meshes.md, "Refinement"), the
// solid counterpart of refine.hpp.
//
// A cell is split around an interior point into one child per corner: each of its geometric
// sides is cut at its midpoint, each of its geometric faces around a face point into one
// quadrilateral per corner, and the interior point is joined to the face points and the side
// midpoints. A new vertex that lands inside an edge or a face of a cell that is not split
// becomes one more vertex of that cell's faces (a hanging vertex; a face the neighbour cut is
// replaced by its pieces: the virtual element method allows any polyhedron), and at most one
// such vertex per geometric side is allowed: neighbours that would carry more are split too.
// Regions, face groups and the boundary follow the refinement, and a prolongation matrix
// interpolates nodal values from the parent mesh onto the refined one.
//
// Every tolerance is relative to the size of a face or a cell: the same mesh at any scale is
// refined the same way. The same input always gives the same numbering.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <span>
#include <vector>

#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// A polyhedral mesh refined from a parent mesh, and how each of its parts came from the
/// parent.
struct RefinedMesh3D {
  /// The refined mesh. Vertex i < parent.num_vertices() is parent vertex i (same position);
  /// new vertices follow, made while walking the split cells in increasing id: for each, the
  /// midpoints of its sides not made before, the points of its faces not made before, then its
  /// interior point. Cells follow the parent's order: a cell that is not split keeps its place
  /// (its faces carrying the new vertices of its neighbours), a split cell is replaced by its
  /// children, one per corner, in increasing id of the corner vertex. Regions are inherited.
  Mesh3D mesh;
  /// Per cell of `mesh`: the parent cell it lies in.
  std::vector<int> parent_cell;
  /// Per face of `mesh`: the parent face it is part of (the whole face, with any new vertices
  /// on its edges, or one of its pieces), or -1 for a face inside a split parent cell.
  std::vector<int> parent_face;
  /// Per vertex of `mesh`, its value as a combination of the parent's vertex values
  /// (num_vertices() x parent.num_vertices(), rows summing to 1, exact for linear fields): an
  /// old vertex keeps its value; a point cut on an edge takes the linear interpolation of the
  /// edge's ends (the mean at a midpoint: exact for the parent's VEM functions, linear on
  /// edges); a face point the face's mean value coordinates; a cell's interior point the
  /// affine combination of the cell's vertices of least Euclidean norm. Apply per component to
  /// interpolate a displacement (see prolongate).
  Eigen::SparseMatrix<double, Eigen::RowMajor> prolongation;
  /// The parent cells that were split, sorted: the marked ones and those the
  /// one-hanging-vertex rule added.
  std::vector<int> refined;
};

/// Splits the marked cells (ids into mesh; duplicates allowed; InputError for an id out of
/// range) and every cell the one-hanging-vertex rule adds.
///
/// Geometric faces, corners and sides. A vertex of a face is hanging there when it lies
/// strictly between its two neighbours along the face's boundary, at a distance from the
/// segment joining them of at most 1e-10 of the face's diameter (taken out nearest first, as
/// element_corners does in the plane; at least 3 corners remain). A cell's geometric faces are
/// its faces, except that two triangles (three corners each) between the same two cells that
/// share a side are one geometric face with four corners (a folded quadrilateral: an interior
/// face this function cut along a diagonal, see below), and that the pieces a split neighbour
/// made of a geometric face (coplanar, or the pieces of a folded one: one corner each, around
/// one vertex inside, meeting on the sides at their midpoints) are one geometric face again.
/// The corners of a cell are the corners of its geometric faces; its geometric sides run along
/// the faces' boundaries from corner to corner, each between two geometric faces. A cube whose
/// neighbours were split has more vertices and faces but 8 corners, 6 geometric faces and 12
/// sides.
///
/// The split. Each side is cut at the midpoint of its end corners: a vertex already there
/// (within 1e-8 of the side's length: the hanging vertex of an earlier split) is reused, else a
/// new vertex is made on the edge that holds the midpoint, shared with every cell around that
/// edge. Each geometric face that is a face of the mesh gets a face point, its centroid when
/// that lies strictly inside the kernel of the polygon of its corners (more than 1e-8 of the
/// face's diameter from every side's line), else the centroid of that kernel; a folded face the
/// midpoint of its diagonal. It is cut into one quadrilateral per corner (corner, side
/// midpoint, face point, previous side midpoint, with the vertices along its sides; on a folded
/// face the pieces at the ends of the diagonal are folded too, cut along the segment from the
/// corner to the face point), and both cells of the face use those pieces. A geometric face made
/// of pieces keeps them, and its point is the vertex they share. The cell's interior point is
/// its centroid when that lies strictly inside the cell's kernel (more than 1e-8 of the
/// diameter inside the plane of every face), else the centroid of the kernel (the cell's
/// bounding box clipped by each face's inner half-space). The child of corner v is the union,
/// over the geometric faces at v, of their pieces at v, joined to the interior point: for each
/// side at v its interior face runs from the side's midpoint to one face point, the interior
/// point and the other face point. That face is one planar quadrilateral when its four points
/// are coplanar (within 1e-12 of its diameter), else the two triangles along the segment from
/// the midpoint to the interior point: the children are then exactly the cones from the
/// interior point over their pieces, every face is planar, and, the two triangles being one
/// folded geometric face at the next split, every child of a cell whose corners are each in
/// three geometric faces again has corners in three geometric faces each, except its own
/// corner and the interior point, which are in as many as the corner was.
///
/// What that gives: a hexahedron splits into its eight sub-hexahedra (a box into the eight
/// boxes of half its sides); a tetrahedron into four hexahedra with planar faces (vertex,
/// three edge midpoints, three face centroids, centroid: the interior faces of a tetrahedron
/// split around its centroid are planar); a prism into six and a pyramid into five cells; a
/// Voronoi cell into one cell per corner. Refining ten times towards a vertex, the cells made
/// keep their shape: diameter^3 / volume stays 5.2 on cubes, grows from 24 to 51 (converging)
/// on Kuhn's tetrahedra, and stays below 37 on make_voronoi3d(3) (tests/test_refine3d.cpp).
/// The split keeps every corner, however close to another or however flat: a cell with a side
/// much shorter than its diameter (Voronoi cells of seeds near a degenerate configuration have
/// sides of 1e-4 of the cell) gets thin children at the ends of that side, and a corner where
/// the faces meet at nearly 180 degrees gets children that flatten under repeated refinement
/// there; such cells are valid but not shape-regular. A cell whose kernel is empty or
/// degenerate cannot be split around an interior point and throws InputError naming it
/// ("cell 17 is not star-shaped: ..."), as does one whose faces do not meet along whole sides
/// (a corner of one face lying inside a side of another: a face made of two coplanar faces
/// other than the pieces above); the same for a cell added by the rule.
///
/// The one-hanging-vertex rule: a cell that is not marked, but one of whose sides (or of the
/// segments from a side midpoint to the point inside a face made of pieces) would receive a
/// new vertex from a split neighbour and then carry more than one vertex strictly inside it
/// (its existing hanging vertices and the new ones counted), is marked too, up to a fixed point.
/// On a mesh whose sides carry at most one vertex each, at their midpoints (every generated
/// mesh and every mesh refine_mesh makes from one), the refined mesh keeps that property, so
/// no face has more than twice as many vertices as corners.
///
/// Children inherit the region of their parent; each piece of a parent face belongs to the
/// face groups of that face, so a group covers the same surface as before; boundary faces
/// stay on the boundary, and the bounding box and the volume do not change. The cost is
/// linear in the size of the mesh. A refined cell that would not be a valid polyhedron (see
/// find_mesh3d_defects) throws MeshError naming the parent cell.
RefinedMesh3D refine_mesh(const Mesh3D& mesh, std::span<const int> marked);

/// Every cell split once (refine_mesh with every cell marked).
RefinedMesh3D refine_uniformly(const Mesh3D& mesh);

/// Interpolates a nodal vector with 3 entries per vertex (x, y, z interleaved) of the parent
/// mesh onto the refined mesh (refined.prolongation applied to each component). Throws
/// InputError when parent_values does not have 3 entries per parent vertex.
Eigen::VectorXd prolongate(const RefinedMesh3D& refined, const Eigen::VectorXd& parent_values);

}  // namespace hemivem
