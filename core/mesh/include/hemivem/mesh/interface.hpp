// Matching the meshes of two bodies along their common contact boundary.
//
// Two bodies meshed independently touch along a curve (the top of one block and the bottom of
// another, a straight or kinked line). Each side's interface is a chain of its boundary edges,
// and the two chains have different vertices. Matching inserts every interface vertex of one
// side into the interface edge of the other side that holds it: the polygon of that edge gains a
// vertex on its side (a hanging vertex, collinear with its neighbours, as the adaptive refinement
// makes: the virtual element method allows any polygon) and the edge is split in two. Afterwards
// both interfaces have the same vertices at the same points, paired one to one, so that the
// discrete contact between the bodies is node to node.
//
// Nothing is moved and nothing is removed: the meshes keep their vertices (with their ids and
// coordinates), their elements (with their ids and regions) and their areas; only vertices are
// added. The same input always gives the same numbering.
#pragma once

#include <array>
#include <vector>

#include <hemivem/mesh/mesh.hpp>

namespace hemivem {

/// Two meshes matched along their interface, and how they came from the given ones.
struct MatchedInterface {
  /// The two meshes with the inserted vertices. Vertex i < n (n the vertices of the given mesh)
  /// is the given vertex i (same position); the inserted vertices follow, in the order of the
  /// other side's interface vertices they copy (walked counter-clockwise around the other body),
  /// each at that vertex's coordinates exactly. Element e is the given element e (same region),
  /// its polygon with the inserted vertices spliced into its interface edges. Edge groups are
  /// inherited: each piece of a split edge belongs to the groups of the edge.
  Mesh first, second;
  /// The interface edges of each mesh after splitting, in the order of `pairs`: first_edges[k]
  /// joins pairs[k][0] and pairs[k + 1][0], second_edges[k] joins pairs[k][1] and pairs[k + 1][1].
  std::vector<int> first_edges, second_edges;
  /// The interface vertices, one pair per point: (vertex of first, vertex of second), ordered
  /// along the interface counter-clockwise around the first body (the direction of its edges;
  /// the second body's run the other way). An inserted vertex has exactly the coordinates of its
  /// partner; two given vertices paired because they coincide keep their own coordinates, which
  /// differ by at most the tolerance (they are bitwise identical when the given ones were).
  std::vector<std::array<int, 2>> pairs;
  /// Per vertex of the given first (second) mesh: its id in `first` (`second`). Vertices keep
  /// their ids (only vertices are added), so these are the identity; they are given so that
  /// callers do not rely on it.
  std::vector<int> first_vertex_of, second_vertex_of;
};

/// Matches the interface `first_edges` of mesh `first` with the interface `second_edges` of mesh
/// `second` (boundary edge ids, in any order; a repeated id counts once).
///
/// Each list must be one open chain of boundary edges (its edges joined end to end, no vertex on
/// more than two of them), and the two chains must cover the same curve from end to end, from
/// opposite sides: the bodies lie on either side of it. The distance tolerance is `tolerance`
/// (in [0, 0.1]) times the interface's length (the longer of the two chains), and at least the
/// round-off of the coordinates (16 machine epsilons of the largest coordinate magnitude of the
/// interfaces' vertices): the same pair of meshes at any scale is matched the same way.
///
/// The match: an interface vertex of one side within the tolerance of an interface vertex of the
/// other is paired with it, and nothing is inserted. Any other interface vertex of one side must
/// lie within the tolerance of an interface edge of the other (the nearest one, the first along
/// the chain on a tie), strictly inside it: it is inserted into that edge, at its own coordinates,
/// and into the polygon of the element that holds the edge, between the edge's end points, in the
/// order of their projections onto the edge. The paired vertices must then come in the same order
/// along both chains (walked in opposite directions). Matching meshes that are matched already
/// changes nothing: the same meshes (bit for bit) and pairs. Swapping the sides swaps the meshes,
/// reverses `pairs` and swaps each pair, and reverses and swaps the edge lists.
///
/// Throws InputError, naming the side ("first" or "second"), the edge or vertex id and what was
/// expected, for: a tolerance that is not in [0, 0.1]; an empty list; an edge id out of range or
/// of an edge that is not on the boundary; edges that do not form one open chain (separate pieces,
/// a closed loop, a vertex on three edges); an interface vertex (an end of a chain, or a vertex
/// inside it) farther than the tolerance from the other side's chain; a vertex within the
/// tolerance of two vertices of the other side (an interface edge shorter than about twice the
/// tolerance: use a smaller one); paired vertices in a different order along the two chains; two
/// chains running the same way (bodies on the same side of the interface, overlapping). A split
/// element that is not a valid polygon (possible only when an inserted vertex is off the edge by
/// about the element's size; see find_mesh_defects) throws MeshError naming the side and the
/// element.
///
/// Cost: O(p q) for interfaces of p and q vertices (every vertex of one is compared with every
/// vertex and edge of the other: about linear in the number of elements for interfaces of about
/// its square root), plus the rebuilding of both meshes, linear in their size.
///
/// Limits: open interfaces only (a body surrounded by the other, whose interface is a closed
/// curve, is not handled); vertices are never moved, so two paired vertices that were a
/// round-off apart stay so (a gap of the contact of at most the tolerance); both chains are
/// straight between consecutive paired points, so they are the same curve to the tolerance.
MatchedInterface match_interface(const Mesh& first, const std::vector<int>& first_edges, const Mesh& second,
                                 const std::vector<int>& second_edges, double tolerance);

}  // namespace hemivem
