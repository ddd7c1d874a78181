// Deterministic mesh generators for a rectangle [x0,x1] x [y0,y1], and (triangles,
// voronoi) for a simple polygon. Every generator returns a validated Mesh (see mesh.hpp);
// the same arguments (including the seed) always give the same mesh, bit for bit.
//
// The rectangle generators take the number of cells per side n (an int: n x n cells) or a
// GridSize {nx, ny} (nx cells along x, ny along y, for domains that are not square).
// Every generator throws InputError for n < 1 (or n > 20000) and for a rectangle that
// is not finite with x0 < x1 and y0 < y1. Vertices on the sides have exactly the
// coordinate x0, x1, y0 or y1, so the boundary edges are exactly the edges on the sides.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh_piece.hpp>
#include <hemivem/row_distribution.hpp>

namespace hemivem {

/// Cells of a rectangle generator: nx along x and ny along y; an int n means n x n.
struct GridSize {
  int nx = 1, ny = 1;
  GridSize(int n) : nx(n), ny(n) {}  // NOLINT(google-explicit-constructor): n x n
  GridSize(int nx_, int ny_) : nx(nx_), ny(ny_) {}
  /// "8", or "[8, 4]" when nx != ny.
  std::string text() const;
  bool operator==(const GridSize&) const = default;
};

/// nx x ny rectangles (squares for n x n on a square domain). Vertex (i, j) has
/// index j*(nx+1) + i; element (i, j) has index j*nx + i.
Mesh make_squares(GridSize n, const Rectangle& domain = {});

/// nx x ny rectangles, each split by its lower-left -> upper-right diagonal into two
/// triangles (2 nx ny elements); vertices as make_squares. Rectangle (i, j) gives element
/// 2(j*nx + i) below the diagonal and 2(j*nx + i) + 1 above it.
Mesh make_triangles(GridSize n, const Rectangle& domain = {});

struct VoronoiOptions {
  std::uint64_t seed = 1;        ///< random seeds are drawn from std::mt19937_64(seed)
  int max_lloyd_iterations = 100;
  /// Lloyd iterations stop when no seed moves by more than this fraction of the
  /// mean seed spacing sqrt(area / n^2). 0 with max_lloyd_iterations = 0: raw Voronoi.
  double lloyd_tolerance = 1e-3;
  /// Across processes, one row per process (hemivem/row_distribution.hpp), or null: the Lloyd
  /// iterations of make_voronoi (on a rectangle) and make_voronoi3d split among them. Each
  /// process computes the cells of an even split of the seeds (in their order; in the plane from
  /// the seeds around them alone) and their centroids, which all_gather gives every process;
  /// every process then makes the whole mesh, the same to the bit as one process makes.
  /// Collective: every process calls the generator alike. Not kept beyond the call.
  const RowDistribution* processes = nullptr;
};

/// Voronoi cells of nx*ny random seeds (uniform in the rectangle), computed with
/// CGAL's Delaunay triangulation of the seeds and their reflections across the
/// four sides, so the cells tile the rectangle exactly; vertices on the sides are
/// placed exactly on them; Lloyd iterations move seeds to cell centroids.
/// Element e is the cell of seed e; seeds are numbered along a Hilbert curve, so nearby
/// cells have nearby numbers. Voronoi vertices closer than a tolerance
/// max(1e-10 * domain size, 1e-7 * seed spacing, 64 eps * largest |coordinate|) are merged
/// into one, so the mesh has no edge shorter than about that; vertices are numbered in
/// order of first appearance when walking the cells in seed order, each cell starting at
/// its lexicographically smallest (x, then y) vertex. Throws InputError for negative max_lloyd_iterations or a
/// negative or non-finite lloyd_tolerance.
Mesh make_voronoi(GridSize n, const Rectangle& domain = {}, const VoronoiOptions& options = {});

/// The piece of make_voronoi's mesh that process `rank` of `size` keeps (MeshPieceRead,
/// hemivem/mesh/mesh_piece.hpp), made without the whole mesh: the seeds' cells as lists of
/// vertices, as make_voronoi numbers them, then the piece chosen among them by the rule of a
/// piece read from a file (read_gmsh_piece; the cells of every boundary edge and around the
/// vertex nearest each point `held`) and only its mesh made. options.processes, when given, are
/// the processes of the run (collective, as make_voronoi).
MeshPieceRead<Mesh> make_voronoi_piece(GridSize n, const Rectangle& domain, const VoronoiOptions& options, int rank,
                                       int size, HeldPoints held = {});
/// The same collectively over `processes` (options.processes set to them), the lists made by the
/// first process alone: every process splits the Lloyd iterations, then the first computes every
/// seed's cell and makes every process's piece in turn and sends it, so that the others never
/// hold the whole mesh's lists. Given a BoundaryPick, the pieces hold of the boundary the cells of
/// the facets it picks alone (read_gmsh_piece across processes). An error in the cells, the pick or
/// the pieces ends every process, the first with it, the others saying that process 0 stopped with
/// it.
MeshPieceRead<Mesh> make_voronoi_piece(GridSize n, const Rectangle& domain, const RowDistribution& processes,
                                       VoronoiOptions options = {}, HeldPoints held = {},
                                       const BoundaryPick<Mesh>& pick = {});

/// make_voronoi's mesh as lists, of which a process makes the piece around any vertices
/// (MeshLists; the pieces make_voronoi_piece makes are among them).
MeshLists<Mesh> voronoi_lists(GridSize n, const Rectangle& domain, const VoronoiOptions& options = {});
/// The same made by the first process of `processes` alone (ListsOfFirst; collective: the Lloyd
/// iterations split among them now, as make_voronoi_piece across processes splits them, and
/// make() computes every seed's cell), of which the first sends every process its pieces
/// (piece_of_lists_by_first).
ListsOfFirst<Mesh> voronoi_lists_of_first(GridSize n, const Rectangle& domain, const RowDistribution& processes,
                                          VoronoiOptions options = {});

/// nx x ny macro cells on a (2nx+1) x (2ny+1) point grid; points whose index sum is odd (side
/// mid-points) are shifted by a quarter of the macro-cell size in x and y; cell
/// centres and mid-points on the domain boundary are dropped. Interior elements are
/// non-convex octagons, boundary ones 7- and 6-gons (N = 1: the rectangle itself).
/// Element (I, J) has index J*nx + I and lists corner (2I,2J), bottom mid-point,
/// corner (2I+2,2J), right mid-point, corner (2I+2,2J+2), top mid-point, corner
/// (2I,2J+2), left mid-point, skipping dropped ones; vertices are the kept grid points
/// in row-major order (j, then i).
Mesh make_nonconvex(GridSize n, const Rectangle& domain = {});

/// nx x ny rectangles whose interior vertices are moved by a uniform random vector in
/// [-fraction*hx, fraction*hx] x [-fraction*hy, fraction*hy] (0 <= fraction < 0.5,
/// else InputError); boundary vertices stay put. Numbering as make_squares.
Mesh make_distorted(GridSize n, double fraction = 0.2, const Rectangle& domain = {}, std::uint64_t seed = 1);

/// The cells of a polar grid around `center`: between consecutive radii r_0 < r_1 < ... < r_m
/// and consecutive angles theta_0 < ... < theta_n (radians, counter-clockwise from the x axis,
/// spanning at most a full turn), quadrilaterals, and triangles at r_0 = 0 (the centre is one
/// vertex): a ring, a disk or a sector of either, graded as the lists say. Vertex (i, j) lies at
/// center + r_i (cos theta_j, sin theta_j), exactly on an axis at the multiples of pi/2, so the
/// vertices on a circle lie on it to round-off and the boundary is a polygon inscribed in the
/// circles. Element (i, j) (the ring i, the sector j) has index j m + i. Edge groups: "outer"
/// (on r_m), "inner" (on r_0 > 0), and unless the angles make a full turn "start" (on theta_0)
/// and "end" (on theta_n). InputError for fewer than two radii or angles (or more than 20001),
/// values that do not increase or are not finite, a negative r_0, or more than a full turn.
Mesh make_polar(const Vec2& center, const std::vector<double>& radii, const std::vector<double>& angles);

/// n + 1 values from `from` to `to` (either way) whose steps grow by `ratio` >= 1 from
/// `from`: h, h ratio, h ratio^2, ..., summing to |to - from|. The first and last values are
/// `from` and `to` exactly. InputError for n < 1, a ratio below 1 or not finite, or values not finite.
std::vector<double> graded_steps(double from, double to, int n, double ratio = 1.0);

/// The radii and angles (radians) of make_polar for a ring between `radii` and `angles`
/// (degrees), `n_radial` cells along the radius growing by `ratio` inwards from radii[1], and
/// `n_around` cells around: growing by `ratio` away from `focus` (degrees, within the angles)
/// on both sides, its cells split between the two sides as their angles are, or uniform
/// without one. InputError for values out of range, naming them.
std::array<std::vector<double>, 2> polar_grid(const std::array<double, 2>& radii, const std::array<double, 2>& angles,
                                              int n_radial, int n_around, double ratio = 1.0,
                                              std::optional<double> focus = std::nullopt);

/// A simple polygon: its corners in order around the boundary (either orientation), the
/// last joined to the first. Edge k runs from corner k to corner k+1.
struct PolygonDomain {
  std::vector<Vec2> corners;
};

// The polygon generators throw InputError naming the defect for fewer than 3 corners, a
// corner that is not finite or above 1e150 in magnitude, a corner repeated by the next, a
// polygon that is not simple (edges that cross or touch), and cells too small for double
// precision. The boundary edges of the mesh on edge k of the polygon form the edge group
// "edge<k>" (Mesh::edge_group), so boundary conditions can name the polygon's edges.
//
// The CGAL generators (make_voronoi, and make_triangles on a polygon) mesh a domain larger than
// 1e30 or smaller than 1e-30 in coordinates divided by a power of two that brings it to about
// unit size (CGAL's Delaunay computations overflow beyond about 1e70), then multiply the mesh
// back: exact, so every domain the checks accept is meshed with sides and corners in place.

/// What is wrong with a polygon domain ("" when nothing): fewer than 3 corners, a corner
/// not finite or above 1e150, a corner repeated by the next, edges that cross or touch.
std::string polygon_domain_defect(const PolygonDomain& domain);

/// Triangles in a polygon: CGAL's constrained Delaunay triangulation of the polygon,
/// refined by CGAL's Delaunay mesher (Delaunay_mesher_2) until no angle is below about
/// 20.7 degrees and no edge is longer than 1.5 sqrt(area)/n: about 2 n^2 triangles, as on a
/// rectangle. Vertices on the polygon's edges lie on them to round-off; elements are
/// numbered along a Hilbert curve through their centroids. Throws InputError naming the
/// feature's width and location for a polygon with a corner closer than 1e-3 of that edge
/// length to an edge it does not end on (a thin spike, slit or neck), and naming the narrowest
/// part when the mesher would make more than 16 n^2 + 4096 triangles.
Mesh make_triangles(int n, const PolygonDomain& domain);

/// Voronoi cells of n*n random seeds uniform in the polygon (drawn in its bounding box
/// from std::mt19937_64(seed), kept when strictly inside), clipped to the polygon with
/// CGAL's exact Boolean operations; Lloyd iterations as on a rectangle (a seed whose cell
/// is cut into pieces whose joint centroid lies outside the polygon stays put). A cell cut
/// into several pieces by a re-entrant corner gives one element per piece, so there may be
/// a few more elements than seeds. Polygon corners are mesh vertices exactly; other
/// vertices on the polygon's edges lie on them to round-off.
Mesh make_voronoi(int n, const PolygonDomain& domain, const VoronoiOptions& options = {});

/// The piece of make_mesh(generator, n, domain, seed)'s mesh in a polygon that process `rank` of
/// `size` keeps (MeshPieceRead), as make_voronoi_piece keeps its piece of a rectangle's: the
/// cells made as lists of vertices, as the whole mesh numbers them, the piece chosen among them
/// by the rule of a piece read from a file and only its mesh made, its edge groups "edge<k>" the
/// whole mesh's edges on them (every piece holds every boundary edge). Errors as make_mesh's.
MeshPieceRead<Mesh> make_mesh_piece(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed,
                                    int rank, int size, HeldPoints held = {});
/// The same collectively over `processes`, the generator run by the first process alone, which
/// makes every process's piece in turn and sends it (make_voronoi_piece across processes); a
/// BoundaryPick is given the piece of the boundary with its edge groups "edge<k>".
MeshPieceRead<Mesh> make_mesh_piece(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed,
                                    const RowDistribution& processes, HeldPoints held = {},
                                    const BoundaryPick<Mesh>& pick = {});

/// make_mesh(generator, n, domain, seed)'s mesh in a polygon as lists (MeshLists), its pieces'
/// edge groups those of make_mesh_piece's.
MeshLists<Mesh> mesh_lists(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed);
/// The same made by the first process alone (ListsOfFirst: make() runs the generator), each
/// piece made of the lists a process receives given its edge groups by finish.
ListsOfFirst<Mesh> mesh_lists_of_first(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed);

/// The generator names: squares, triangles, voronoi, nonconvex, distorted.
const std::vector<std::string>& mesh_generator_names();

/// Any generator by name with its default options; throws InputError listing the
/// valid names for an unknown one. `processes`: across processes, voronoi's Lloyd iterations
/// split among them (VoronoiOptions::processes; collective); the other generators do not use it.
Mesh make_mesh(std::string_view generator, GridSize n, const Rectangle& domain = {}, std::uint64_t seed = 1,
               const RowDistribution* processes = nullptr);

/// triangles or voronoi by name in a polygon; InputError for the other generators (they
/// need a rectangle) and for an unknown name.
Mesh make_mesh(std::string_view generator, int n, const PolygonDomain& domain, std::uint64_t seed = 1);

}  // namespace hemivem
