// A grid sequence (solver.grid_sequence, docs/full-space.md): the full-space route solves a scene
// on a generated grid of boxes first on coarser grids, each with half as many boxes along every
// axis as the next, and starts each solve from the one before carried onto its grid
// (values_on_finer_grid, hemivem/mesh/finer_grid.hpp). The Newton iteration on the scene's own
// grid then starts near its answer and needs fewer iterations; the answer is the scene's,
// certified on its own grid.
#pragma once

#include <Eigen/Core>

#include <hemivem/scene/scene.hpp>

namespace hemivem {

/// The fewest boxes along each axis that `solver.grid_sequence = "auto"` leaves a coarser grid.
inline constexpr int grid_sequence_auto_boxes = 16;

/// The coarser grids a static solve of `scene` starts from: solver.grid_sequence when it gives
/// a count; with "auto", as many as halve every axis's count of boxes exactly while each keeps
/// at least grid_sequence_auto_boxes of them, on the full-space route (`full_space`) of a static
/// solve (`path` false) of a scene made in pieces (scene_piece, hemivem/scene/scene_pieces.hpp),
/// none otherwise. InputError naming solver.grid_sequence for a count that the route, a path or
/// the mesh does not allow (each coarser grid needs an even count of at least 2 boxes along
/// every axis to halve).
int grid_sequence_levels(const Scene& scene, bool full_space, bool path);

/// `scene` on the grid of half as many boxes along every axis (mesh.n halved), with no grid
/// sequence of its own (solver.grid_sequence = 0). InternalError for an odd count.
Scene coarser_grid_scene(const Scene& scene);

/// A displacement `u` of the mesh of `grid` (a scene of coarser_grid_scene) carried onto the
/// grid with twice as many boxes along every axis (values_on_finer_grid, dimension() numbers a
/// vertex). InputError as values_on_finer_grid.
Eigen::VectorXd carried_onto_finer_grid(const Scene& grid, const Eigen::VectorXd& u);

}  // namespace hemivem
