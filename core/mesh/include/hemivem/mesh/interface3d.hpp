// Matching the meshes of two solids along their common contact surface, the solid counterpart
// of interface.hpp.
//
// Two solids meshed independently touch along a plane surface (the top of one block and the
// bottom of another). Each side's interface is a set of its boundary faces, and the two sets
// subdivide the same plane region differently. Matching replaces both subdivisions by their
// common refinement (the overlay): every interface face of either side is replaced by the
// polygons in which the faces of the other side cut it, and the points where the two sides'
// interface edges cross, and each side's interface vertices, become vertices of both meshes. A
// point inserted into an interface edge is also inserted into every other face of the mesh that
// holds that edge (the side faces of the cells along it: a hanging vertex, collinear with its
// neighbours, as the adaptive refinement makes; the virtual element method allows any polygonal
// face), so that the mesh stays conforming. Afterwards both interfaces are the same polygons
// with the same vertices at the same points, paired one to one, so that the discrete contact
// between the bodies is node to node and face to face.
//
// Nothing is moved and nothing is removed: the meshes keep their vertices (with their ids and
// coordinates), their cells (with their ids and regions) and their volumes; vertices are added
// and interface faces are split. The same input always gives the same numbering.
#pragma once

#include <array>
#include <vector>

#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// Two solid meshes matched along their interface.
struct MatchedInterface3D {
  /// The two meshes with the inserted vertices and the split interface faces. Vertex i < n (n the
  /// vertices of the given mesh) is the given vertex i (same position); the inserted vertices
  /// follow: first copies of the other side's interface vertices that this side does not have
  /// (in increasing id of the other side), then the crossings of the two sides' interface edges
  /// (in increasing order of the first mesh's interface edges, by their sorted end vertex ids,
  /// and along each edge from its smaller end). A copy has the coordinates of the vertex it
  /// copies, and both copies of a crossing have the coordinates computed on the first side's
  /// edge, bit for bit, unless they lie off the edge (or the plane of the face) they are
  /// inserted into by more than 1e-11 of its size (a vertex placed there within the tolerance):
  /// then the copy is their projection onto it, so that the faces along the edge stay straight
  /// and planar. Cell c is the given cell c (same region): an interface face of it is replaced by
  /// its pieces, in increasing order of the other side's face they lie in, and every other face
  /// holding an interface edge that received points has them spliced in between the edge's ends.
  /// Face groups are inherited: each piece of a split face, and each face that gained vertices,
  /// belongs to the groups of the face it came from. Face ids are those Mesh3D gives (first
  /// appearance in cell order).
  Mesh3D first, second;
  /// The interface faces of each mesh after the match, paired: first_faces[k] and
  /// second_faces[k] are the same polygon (the same points, pairs mapping one onto the other),
  /// with opposite orientations. Sorted by first_faces.
  std::vector<int> first_faces, second_faces;
  /// The interface vertices, one pair per point: (vertex of first, vertex of second), sorted by
  /// the vertex of first. An inserted vertex has the coordinates of its partner and the two
  /// copies of an edge crossing are bitwise identical (but for the projections above, which
  /// move a copy by at most the tolerance); two given vertices paired because they coincide keep
  /// their own coordinates, which differ by about the tolerance at most (they are bitwise
  /// identical when the given ones were).
  std::vector<std::array<int, 2>> pairs;
};

/// Matches the interface `first_faces` of mesh `first` with the interface `second_faces` of mesh
/// `second` (boundary face ids, in any order; a repeated id counts once).
///
/// The two interfaces must lie in one plane and cover the same region of it, from opposite
/// sides: the outward normals of the first side's faces point one way and those of the second
/// side's the other (the bodies lie on either side of the plane). The plane is the one through
/// the area-weighted centroid of the first side's faces, normal to the sum of their area
/// vectors; the region need not be convex or connected. Every interface face must be convex
/// (an angle of 180 degrees, at a vertex lying on the segment between its neighbours, is
/// allowed): a non-convex face is refused by name, not triangulated. The distance tolerance is
/// `tolerance` (in [0, 0.1]) times the interface's size (the larger diagonal of the bounding
/// boxes of the two sides' interface vertices), and at least the round-off of the coordinates
/// (16 machine epsilons of the largest coordinate magnitude of the interfaces' vertices): the
/// same pair of meshes at any scale is matched the same way.
///
/// The match, in the plane of the interface (coordinates in a fixed orthonormal frame of it):
/// an interface vertex of one side within the tolerance of an interface vertex of the other, or
/// within the tolerance of two interface edges of the other that share a vertex (it is within
/// reach of both, so at their common end), is paired with that vertex, and nothing is inserted;
/// a pair is made when either vertex is so placed at the other. Any other interface vertex of
/// one side must lie within the tolerance of an interface edge of the other (the nearest, the
/// first in id order on a tie: it is inserted into that edge) or inside one of its faces (it
/// becomes a vertex of the pieces of that face). Two edges, one of each side, cross when the
/// ends of each lie on either side of the other's line, each farther than the tolerance from it;
/// the crossing is computed once, on the edge of the first side, and inserted into both edges.
/// The pieces of a first face f and a second face g are the points inside or on the boundary of
/// both (by the combinatorial places above, not by a new geometric test), ordered around their
/// mean, when the two faces overlap: when those points include a crossing or a point inside f
/// or g, or two points on one edge of one face that are not both within the tolerance of the
/// line of one edge of the other (a chord through it), or else span an area larger than the
/// tolerance times their diameter (faces that only touch along an edge give points along a
/// line). Every point on a piece's boundary is its vertex, so neighbouring pieces share their
/// edges. A face whose piece is the face itself (the same vertices) keeps its vertex loop:
/// matching meshes that are matched already changes nothing, the same meshes (bit for bit),
/// faces and pairs.
///
/// Throws InputError, naming the side ("first" or "second"), the face or vertex id and what was
/// expected, for: a tolerance that is not in [0, 0.1]; an empty list; a face id out of range or
/// of a face that is not on the boundary; an interface that is not planar (a vertex of either
/// side off the plane by more than the tolerance: piecewise-planar interfaces, an L-shaped step,
/// are refused); a first face whose normal points against the others; the second side's faces
/// facing the same way as the first's (the bodies overlap); a non-convex interface face; an
/// interface vertex of one side outside the other side's interface by more than the tolerance,
/// or within the tolerance of two vertices of the other side (or of edges around two of them), or
/// two vertices pairing with one (use a smaller tolerance); and
/// interfaces whose pieces do not cover a face of either side (the regions differ where no
/// vertex shows it, e.g. an edge of one side cutting across a notch of the other), the area left
/// uncovered being more than the tolerance times the face's perimeter. A side that is not a
/// valid mesh after the match (see the limits) throws MeshError naming the side and the cell.
///
/// Cost: about linear in the number of interface faces (the faces of each side are bucketed on
/// a grid over the interface, so each vertex and edge is compared with the few faces of the
/// other side near it), plus the rebuilding of both meshes, linear in their size: about 0.1 s
/// for 3600 squares against 3500 triangles.
///
/// Limits: one plane only; convex interface faces only; nothing on the given interface is moved,
/// so paired vertices that were a tolerance apart stay so. Two sides whose vertices and edges
/// come closer than a few tolerances without coming within one can make pieces thinner than
/// about twice the tolerance, which the places above do not always resolve consistently (a
/// vertex placed on an edge within the tolerance while that edge also passes a few tolerances
/// from it elsewhere, or a sliver piece taken for two faces touching along an edge): the match
/// then throws MeshError (a side whose cell is not closed) or InputError (a face not covered).
/// A 4 x 4 grid of squares against the same grid of triangles with its inner vertices moved by
/// up to 7 tolerances fails so for about one move in eight; with a tolerance 100 times smaller
/// (points then far apart) or larger (points then paired) every such move matches.
MatchedInterface3D match_interface_3d(const Mesh3D& first, const std::vector<int>& first_faces, const Mesh3D& second,
                                      const std::vector<int>& second_faces, double tolerance);

}  // namespace hemivem
