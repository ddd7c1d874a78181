// Memory needed by a solve, estimated before anything is allocated, and the memory the
// machine offers. A request that cannot fit is refused up front with the estimate, instead of
// being killed by the operating system halfway through.
//
// The model (docs/stability.md, "Memory"): peak resident memory of one solve with any linear
// engine is about 32 MiB + c * V * log2(V) bytes for a mesh of V vertices, with c = 280 for
// meshes of quadrilaterals and triangles and c = 500 for polygonal meshes (Voronoi, non-convex,
// meshes read from files), fitted to measured peaks of `hemivem solve` on Example 4.1 for
// N = 128 ... 512 (squares 86 MB ... 1.25 GB, Voronoi 255 MB ... 1.1 GB) and within 20 % of them.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace hemivem {

struct MemoryEstimate {
  double vertices = 0.0;      ///< vertices of the mesh (counted or predicted)
  double mesh_bytes = 0.0;    ///< the mesh alone (coordinates, elements, edges, generator work)
  double solve_bytes = 0.0;   ///< peak of a whole solve (mesh, assembly, factorization, outputs)
  double element_matrix_entries = 0.0;  ///< sum over the elements of (2 m)^2, m vertices each (0: not counted)
};

class Mesh;

/// The full-space route's memory (docs/full-space.md), which grows with the vertices alone (no
/// factor, no Schur complement): the process with the engine's libraries and the bytes per
/// vertex, fitted on measured peaks of each Krylov engine with 20 % added.
struct FullSpaceCost {
  double base_bytes = 0.0;
  double bytes_per_vertex = 0.0;
};
/// The cost for a mesh generator and a Krylov engine (petsc-gamg, petsc-hypre, eigen-cg): per
/// vertex from 2.9 KB (the plane, petsc-gamg) to 46 KB (Voronoi cells in a
/// solid, eigen-cg).
FullSpaceCost full_space_cost(int dimension, std::string_view generator, std::string_view engine);
/// `condensed` (an estimate of the condensed route for the same mesh) with the solve's bytes
/// of the full-space route.
MemoryEstimate full_space_memory(const MemoryEstimate& condensed, const FullSpaceCost& cost);

/// The estimate for a mesh generator (mesh_generator_names()) with n cells per side.
/// Throws InputError for an unknown generator or n < 1.
MemoryEstimate estimate_memory(std::string_view generator, std::int64_t n);
/// The same with nx cells along x and ny along y (mesh.n = [nx, ny]).
MemoryEstimate estimate_memory(std::string_view generator, std::int64_t nx, std::int64_t ny);
/// The estimate for a mesh of `vertices` vertices whose elements have on average
/// `vertices_per_element` vertices.
MemoryEstimate estimate_memory(double vertices, double vertices_per_element);

/// The estimate for a mesh at hand: its vertices, and its element matrices, which grow with the
/// square of an element's vertex count (an element of 3000 vertices alone needs about 2.5 GB):
/// the larger of the two models.
MemoryEstimate estimate_memory(const Mesh& mesh);
/// The same for a mesh of `vertices` vertices and `elements` elements, the sums over them of their
/// vertex counts being `corners` and of those counts' squares `corners_squared`.
MemoryEstimate estimate_memory(double vertices, double elements, double corners, double corners_squared);

/// A three-dimensional solve (docs/three-dimensions.md): the factor of a 3D stiffness grows like
/// V^(4/3) (nested dissection), far faster than in 2D, and the dense Schur complement on the
/// contact nodes like their square: 24 MiB + 1200 V^(4/3) + 48 n_c^2 bytes for V vertices and
/// n_c contact nodes, 1.1 times the measured peaks of solves on cubes n = 12 ... 32 (66 MB ...
/// 1.3 GB). mesh_bytes: 24 MiB + 1500 V.
/// `per_vertex`, the coefficient of V^(4/3): 1200 for cubes and tetrahedra; Voronoi cells, with
/// their many faces and vertices per cell, couple each vertex with more neighbours and fill
/// their factor more: 3600, 1.1 times the peak measured at n = 16 (2.8 GB, 27 861 vertices).
MemoryEstimate estimate_memory_3d(double vertices, double contact_nodes, double per_vertex = 1200.0);
/// The estimate for a 3D generator (cubes, tetrahedra, voronoi) with nx x ny x nz cells, the
/// contact nodes taken as the vertices of the largest side; InputError for an unknown generator
/// or a size below 1.
MemoryEstimate estimate_memory_3d(std::string_view generator, std::int64_t nx, std::int64_t ny, std::int64_t nz);

/// Bytes the run may use (a run across processes: all of them together): the environment
/// variable HEMIVEM_MEMORY_LIMIT when set (a number of bytes with an optional suffix K, M, G or
/// T, powers of 1024), else MemAvailable of /proc/meminfo; +inf when neither is known. Throws
/// InputError naming the variable when HEMIVEM_MEMORY_LIMIT is malformed.
double available_memory();

/// While an object of this class lives, the process is one of `processes` of a run under a
/// launcher, and require_memory() checks what they take together (run_memory()) against the
/// memory available: of one machine, where the launcher started them (MemAvailable), or the
/// run's whole allocation (HEMIVEM_MEMORY_LIMIT, docs/cluster.md). On the full-space route
/// each process holds its share of the problem and, besides it, what every process holds: its
/// libraries (`base_bytes`) and a part of the problem's estimate (kHeldByEveryProcess: the arrays
/// indexed by the whole mesh, the cells along its boundary, the gathered solution). On the
/// condensed route (`whole_on_each`: mumps-mpi) every process builds and assembles the whole
/// problem. The latest object alive is the one that counts; the process's, not a thread's.
class MemoryOfProcesses {
 public:
  MemoryOfProcesses(int processes, bool whole_on_each, double base_bytes);
  ~MemoryOfProcesses();
  MemoryOfProcesses(const MemoryOfProcesses&) = delete;
  MemoryOfProcesses& operator=(const MemoryOfProcesses&) = delete;

  /// The part of a problem's estimate in one process (less its libraries) that every process
  /// of the full-space route holds besides its share, measured (docs/cluster.md).
  static constexpr double kHeldByEveryProcess = 0.05;

 private:
  int processes_;
  bool whole_on_each_;
  double base_bytes_;
  friend double run_memory(double bytes);
  friend int run_processes();
};

/// What the run's processes take together (MemoryOfProcesses) for a problem whose estimate in
/// one process is `bytes`: `bytes` itself in a run of one process; P * bytes where every process
/// holds the whole; else bytes + (P - 1) * (base + kHeldByEveryProcess * (bytes - base)).
double run_memory(double bytes);
/// The processes of the run (MemoryOfProcesses), 1 outside one.
int run_processes();
/// What the run's processes (run_processes()) would take together on the full-space route,
/// whichever route the run takes, for a problem whose estimate in one process is `bytes`,
/// `base_bytes` of it the libraries: bytes + (P - 1) * (base + kHeldByEveryProcess * (bytes -
/// base)) (the route a refusal on the condensed route advises).
double full_space_run_memory(double bytes, double base_bytes);

/// Throws InputError (at `where`) when run_memory(bytes) exceeds available_memory(); the
/// message gives the estimate (across processes, with one process's), what it is for (`what`,
/// e.g. "squares n = 1000000: 1.0e12 vertices") and the limit with where it came from, and
/// `advice` (what to do instead; by default a smaller mesh).
void require_memory(double bytes, const std::string& what, const std::string& where,
                    const std::string& advice = "use a smaller mesh");

/// "1.2 GiB", "340 MiB", ...
std::string format_bytes(double bytes);

}  // namespace hemivem
