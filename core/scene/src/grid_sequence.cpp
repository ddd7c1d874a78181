#include <hemivem/scene/grid_sequence.hpp>

#include <array>
#include <string>

#include <hemivem/error.hpp>
#include <hemivem/mesh/finer_grid.hpp>
#include <hemivem/scene/scene_pieces.hpp>

namespace hemivem {
namespace {

// The boxes along each axis of the scene's grid (two in the plane).
std::array<int, 3> boxes_of(const Scene& scene, int& axes) {
  if (scene.dimension() == 3) {
    const GridSize3 n = scene.mesh.cells3();
    axes = 3;
    return {n.nx, n.ny, n.nz};
  }
  const GridSize n = scene.mesh.cells();
  axes = 2;
  return {n.nx, n.ny, 0};
}

// How often every axis's count halves exactly while each keeps at least `fewest` boxes.
int halvings(const Scene& scene, int fewest) {
  int axes = 0;
  std::array<int, 3> n = boxes_of(scene, axes);
  int levels = 0;
  for (;;) {
    for (int a = 0; a < axes; ++a)
      if (n[a] % 2 != 0 || n[a] / 2 < fewest) return levels;
    for (int a = 0; a < axes; ++a) n[a] /= 2;
    ++levels;
  }
}

// Whether the scene's coarser grids are its grid's halvings: a grid of boxes whose vertices lie
// where its coarser grids' do (not a distorted one's, whose inner vertices each move at random,
// nor a nonconvex one's, whose mid-points move with the boxes' size; nor a polar grid, whose
// vertices close around a turn and at a centre),
// without region boxes (a coarser cell's centroid lies elsewhere), whose every support, load and
// contact part selects sides alone (a point or a segment may fall between a coarser grid's
// vertices).
bool coarsens(const Scene& scene) {
  if (scene.mesh.generator == "distorted" || scene.mesh.generator == "nonconvex" || scene.mesh.generator == "polar")
    return false;
  if (scene.material.has_region_boxes()) return false;
  return every_selector(scene, [](const BoundarySelector& b) { return b.points.empty() && b.segments.empty(); });
}

}  // namespace

int grid_sequence_levels(const Scene& scene, bool full_space, bool path) {
  const int asked = scene.solver.grid_sequence;
  if (asked == 0) return 0;
  const bool grid = scene_piece(scene, 0, 1).has_value() && coarsens(scene);
  if (asked == SceneSolver::grid_sequence_auto)
    return full_space && !path && grid ? halvings(scene, grid_sequence_auto_boxes) : 0;
  const auto refuse = [&](const std::string& why) {
    throw InputError("solver.grid_sequence = " + std::to_string(asked) + ": " + why, scene.where("solver.grid_sequence"));
  };
  if (!full_space) refuse("a grid sequence runs on the full-space route only (solver.linear a Krylov engine)");
  if (path) refuse("a loading path starts each step from the step before, not from coarser grids");
  if (!grid)
    refuse("a grid sequence needs a mesh generated on a grid of boxes (squares, triangles, cubes or tetrahedra) of "
           "one body whose supports, loads and contact select sides, without region boxes or adaptive steps");
  const int most = halvings(scene, 1);
  if (asked > most)
    refuse("mesh.n = " + scene.mesh.n_text() +
           " halves exactly into " + std::to_string(most) + " coarser grid" + (most == 1 ? "" : "s") + " at most");
  return asked;
}

Scene coarser_grid_scene(const Scene& scene) {
  Scene coarse = scene;
  SceneMesh& m = coarse.mesh;
  const auto half = [](int n) {
    if (n % 2 != 0) throw InternalError("a coarser grid of an odd count of boxes");
    return n / 2;
  };
  m.n = half(m.n);
  if (m.ny) m.ny = half(*m.ny);
  if (m.nz) m.nz = half(*m.nz);
  coarse.solver.grid_sequence = 0;
  return coarse;
}

Eigen::VectorXd carried_onto_finer_grid(const Scene& grid, const Eigen::VectorXd& u) {
  const int dim = grid.dimension();
  return dim == 3 ? values_on_finer_grid(u, grid.mesh.cells3(), dim) : values_on_finer_grid(u, grid.mesh.cells(), dim);
}

}  // namespace hemivem
