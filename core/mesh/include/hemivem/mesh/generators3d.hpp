// Deterministic generators of polyhedral meshes on a box [x0,x1] x [y0,y1] x [z0,z1]
// (docs/three-dimensions.md). Every generator returns a validated Mesh3D; the same arguments
// (the seed included) always give the same mesh, bit for bit. Vertices on the sides of the box
// have exactly the coordinate x0, x1, y0, y1, z0 or z1, so the boundary faces are exactly the
// faces on the sides. Every generator throws InputError for a size below 1 (or above 1000 per
// axis) and for a box that is not finite with x0 < x1, y0 < y1, z0 < z1.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/mesh/mesh_piece.hpp>

namespace hemivem {

/// Cells of a box generator: nx along x, ny along y, nz along z; an int n means n x n x n.
struct GridSize3 {
  int nx = 1, ny = 1, nz = 1;
  GridSize3(int n) : nx(n), ny(n), nz(n) {}  // NOLINT(google-explicit-constructor): n x n x n
  GridSize3(int nx_, int ny_, int nz_) : nx(nx_), ny(ny_), nz(nz_) {}
  /// "8", or "[8, 4, 2]" when the three differ.
  std::string text() const;
  bool operator==(const GridSize3&) const = default;
};

/// nx x ny x nz hexahedra (boxes). Vertex (i, j, k) has index (k (ny+1) + j)(nx+1) + i; cell
/// (i, j, k) has index (k ny + j) nx + i.
Mesh3D make_cubes(GridSize3 n, const Box& domain = {});

/// Boxes on the rectilinear grid of the given coordinates (each list strictly increasing, at
/// least two values): a graded mesh, e.g. fine near a contact and coarse far from it. Numbering
/// as make_cubes with nx = x.size() - 1 etc.; the domain is [x.front(), x.back()] x ... .
/// InputError for a list that is too short, not increasing or not finite.
Mesh3D make_cubes(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z);

/// Each box of make_cubes split into six tetrahedra around its diagonal from corner (0,0,0) to
/// (1,1,1) (Kuhn's subdivision: conforming across boxes); vertices as make_cubes, box b gives
/// cells 6b ... 6b+5.
Mesh3D make_tetrahedra(GridSize3 n, const Box& domain = {});
/// The same on the grid of coordinate lists (as make_cubes of them), each point moved by `place`
/// when given (a map of the box onto a curved body, e.g. a block whose face is a sphere; every
/// face stays a triangle). InputError as make_cubes; MeshError for a map that turns a
/// tetrahedron inside out.
Mesh3D make_tetrahedra(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
                       const std::function<Vec3(const Vec3&)>& place = {});

/// Voronoi cells of nx*ny*nz random seeds (uniform in the box), clipped to the box, with Lloyd
/// iterations moving seeds to cell centroids (VoronoiOptions as in 2D: the seed, the number of
/// iterations, the tolerance relative to the mean seed spacing (volume / seeds)^(1/3)). Cell c is
/// the cell of seed c. Vertices closer than a tolerance are merged, so faces conform exactly.
Mesh3D make_voronoi3d(GridSize3 n, const Box& domain = {}, const VoronoiOptions& options = {});

/// The piece of make_voronoi3d's mesh that process `rank` of `size` keeps, made without the
/// whole mesh, as make_voronoi_piece makes a plane one's (hemivem/mesh/generators.hpp).
MeshPieceRead<Mesh3D> make_voronoi3d_piece(GridSize3 n, const Box& domain, const VoronoiOptions& options, int rank,
                                           int size, HeldPoints held = {});
/// The same collectively over `processes`, the first process alone computing every seed's cell
/// and sending every process its piece, as make_voronoi_piece across processes.
MeshPieceRead<Mesh3D> make_voronoi3d_piece(GridSize3 n, const Box& domain, const RowDistribution& processes,
                                           VoronoiOptions options = {}, HeldPoints held = {},
                                           const BoundaryPick<Mesh3D>& pick = {});

/// make_voronoi3d's mesh as lists (MeshLists), as voronoi_lists makes a plane one's.
MeshLists<Mesh3D> voronoi3d_lists(GridSize3 n, const Box& domain, const VoronoiOptions& options = {});
/// The same made by the first process of `processes` alone, as voronoi_lists_of_first makes a
/// plane one's.
ListsOfFirst<Mesh3D> voronoi3d_lists_of_first(GridSize3 n, const Box& domain, const RowDistribution& processes,
                                              VoronoiOptions options = {});

/// The 3D generator names: cubes, tetrahedra, voronoi.
const std::vector<std::string>& mesh3d_generator_names();

/// Any 3D generator by name with its default options; InputError listing the valid names for
/// an unknown one. `processes`: across processes, voronoi's Lloyd iterations split among them
/// (VoronoiOptions::processes; collective); the other generators do not use it.
Mesh3D make_mesh3d(std::string_view generator, GridSize3 n, const Box& domain = {}, std::uint64_t seed = 1,
                   const RowDistribution* processes = nullptr);

}  // namespace hemivem
