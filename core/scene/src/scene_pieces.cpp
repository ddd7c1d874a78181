// A scene's mesh made in pieces across processes (hemivem/scene/scene_pieces.hpp).
#include <hemivem/scene/scene_pieces.hpp>

#include <hemivem/contact/pose_share.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/bodies.hpp>
#include <hemivem/mesh/dimension.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/mesh/mesh_piece.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/support/names.hpp>
#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include "scene_problem.hpp"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>
#include <tuple>
#include <string>
#include <vector>

namespace hemivem {

namespace {

/// Whether the scene's mesh is a polar grid (make_polar): its sectors along x, its rings along y.
bool is_polar(const Scene& scene) { return scene.mesh.file.empty() && scene.mesh.generator == "polar"; }

/// The boxes along each axis of the scene's generated grid.
std::array<int, 3> grid_counts(const Scene& scene) {
  if (scene.dimension() == 3) {
    const GridSize3 c = scene.mesh.cells3();
    return {c.nx, c.ny, c.nz};
  }
  const GridSize c = scene.mesh.cells();
  return is_polar(scene) ? std::array<int, 3>{c.ny, c.nx, 1} : std::array<int, 3>{c.nx, c.ny, 1};
}

/// How the scene's generator numbers the vertices of its grid.
BoxGridVertices grid_vertices_of(const Scene& scene) {
  if (is_polar(scene)) {
    const auto [radii, angles] = detail::polar_lists(scene);
    return BoxGridVertices("polar", 2, grid_counts(scene), polar_closure(radii, angles));
  }
  return BoxGridVertices(scene.mesh.generator, scene.dimension(), grid_counts(scene));
}

/// The vertex at the grid point of the scene's generated box nearest to `q`: the box corner
/// within half a box of the vertex a support at `q` holds (the vertex nearest to `q`; a
/// distorted or nonconvex mesh's vertices lie off the grid points by less than half a box, so
/// the boxes within two of the corner hold every cell around it). Of a polar grid, the vertex
/// nearest to `q` itself, which the support holds.
int nearest_grid_vertex(const Scene& scene, const std::array<double, 3>& q) {
  const int dim = scene.dimension();
  if (is_polar(scene)) {
    const auto [radii, angles] = detail::polar_lists(scene);
    const Mesh vertices = make_polar_piece(Vec2(scene.mesh.center[0], scene.mesh.center[1]), radii, angles, BoxPiece{});
    return std::max(0, nearest_point<2>(vertices.vertices(), Vec2(q[0], q[1])).first);
  }
  const std::array<int, 3> n = grid_counts(scene);
  std::array<double, 6> box{};
  if (dim == 3) box = scene.mesh.box;
  else std::copy(scene.mesh.domain.begin(), scene.mesh.domain.end(), box.begin());
  std::array<long long, 3> point{0, 0, 0};
  for (int a = 0; a < dim; ++a) {
    const auto s = static_cast<std::size_t>(a);
    const double t = (q[s] - box[2 * s]) / (box[2 * s + 1] - box[2 * s]) * n[s];
    point[s] = std::isfinite(t) ? std::llround(std::clamp(t, 0.0, static_cast<double>(n[s]))) : 0;
  }
  return static_cast<int>(grid_vertices_of(scene).corner(point));
}

/// The side of a polar grid's boxes along its edge group `group` (make_polar's: start, end,
/// inner, outer); empty for another name.
std::string polar_side(const std::string& group) {
  if (group == "start") return "left";
  if (group == "end") return "right";
  if (group == "inner") return "bottom";
  if (group == "outer") return "top";
  return {};
}

/// The side of the scene's rectangle along whose line the segment lies (both its ends within the
/// selector's tolerance of the line); empty when none.
std::string side_along(const Scene& scene, const std::array<double, 4>& segment, double relative_tolerance) {
  const auto& d = scene.mesh.domain;
  const double tolerance = relative_tolerance * std::max(d[1] - d[0], d[3] - d[2]);
  const auto on = [&](double a, double b, double line) { return std::abs(a - line) <= tolerance && std::abs(b - line) <= tolerance; };
  if (on(segment[0], segment[2], d[0])) return "left";
  if (on(segment[0], segment[2], d[1])) return "right";
  if (on(segment[1], segment[3], d[2])) return "bottom";
  if (on(segment[1], segment[3], d[3])) return "top";
  return {};
}

/// Adds to `piece` what the scene's selector `b` needs of its generated box: the sides it names
/// and those its segments lie along (in the plane), whose every cell the piece holds, and the
/// vertex each of its points holds; false when `b` selects by anything else (a group), which a
/// process cannot place before the mesh is made. A segment along no side, or any of a polar
/// grid's, holds every side: the piece knows the facets where it meets the others
/// (grid_cut_facets), which no selector picks, so that the segment picks on it the whole mesh's
/// boundary edges it picks.
bool add_selector(const Scene& scene, const BoundarySelector& b, BoxPiece& piece) {
  const auto every_side = [&] { piece.sides.insert(piece.sides.end(), {"left", "right", "bottom", "top"}); };
  if (is_polar(scene)) {  // its edge groups, the sides of its grid of boxes
    if (!b.segments.empty()) every_side();
    // a side of its bounding box picks boundary edges alone, which the grid's sides hold (a
    // piece's boundary inside the grid lies along no side of the box: a cell beyond it would)
    if (!b.sides.empty()) piece.sides.insert(piece.sides.end(), {"left", "right", "bottom", "top"});
    for (const std::string& group : b.groups) {
      const std::string side = polar_side(group);
      if (side.empty()) return false;
      piece.sides.push_back(side);
    }
    for (const auto& q : b.points) piece.held.push_back(nearest_grid_vertex(scene, q));
    return true;
  }
  if (!b.groups.empty()) return false;
  for (const auto& segment : b.segments) {
    const std::string side = scene.dimension() == 2 ? side_along(scene, segment, b.tolerance) : std::string();
    if (!side.empty()) {
      piece.sides.push_back(side);
    } else {
      if (scene.dimension() != 2) return false;
      every_side();
    }
  }
  piece.sides.insert(piece.sides.end(), b.sides.begin(), b.sides.end());
  for (const auto& q : b.points) piece.held.push_back(nearest_grid_vertex(scene, q));
  return true;
}

/// The vertices of the scene's generated mesh.
long long scene_vertices(const Scene& scene) { return grid_vertices_of(scene).count(); }

/// The piece of the generated box of a scene of one body whose supports, loads and contact
/// parts, and the selectors `more`, select sides, segments (in the plane) and points only
/// (add_selector); none otherwise. With `contact_sides`, of the sides only those of the contact
/// parts (and of `more`) are held, and of the supports and loads their points alone: each
/// process's piece then holds the facets of the supports and loads around its own vertices, and
/// the processes complete them together (build_problem_piece).
std::optional<BoxPiece> box_piece_of(const Scene& scene, const std::vector<BoundarySelector>& more, int rank, int size,
                                     bool contact_sides = false) {
  const SceneMesh& m = scene.mesh;
  if (!m.file.empty() || !makes_pieces(m.generator) || !m.polygon.empty()) return std::nullopt;
  BoxPiece piece;
  const auto place = [&](const BoundarySelector& b) { return add_selector(scene, b, piece); };
  const auto place_points = [&](const BoundarySelector& b) {
    BoxPiece alone;
    if (!add_selector(scene, b, alone)) return false;
    piece.held.insert(piece.held.end(), alone.held.begin(), alone.held.end());
    return true;
  };
  if (contact_sides) {
    bool placed = place_points(scene.clamped);
    for (const SceneDirichlet& d : scene.dirichlet) placed = placed && place_points(d.boundary);
    for (const SceneTraction& t : scene.tractions) placed = placed && place_points(t.boundary);
    for (const SceneContact& c : contact_parts(scene)) placed = placed && place(c.boundary);
    if (!placed || !std::all_of(more.begin(), more.end(), place)) return std::nullopt;
  } else if (!every_selector(scene, place) || !std::all_of(more.begin(), more.end(), place)) {
    return std::nullopt;
  }
  std::sort(piece.sides.begin(), piece.sides.end());
  piece.sides.erase(std::unique(piece.sides.begin(), piece.sides.end()), piece.sides.end());
  std::sort(piece.held.begin(), piece.held.end());
  piece.held.erase(std::unique(piece.held.begin(), piece.held.end()), piece.held.end());
  const long long vertices = scene_vertices(scene);
  if (vertices > std::numeric_limits<int>::max()) return std::nullopt;
  std::tie(piece.first_vertex, piece.end_vertex) = vertex_share(static_cast<int>(vertices), rank, size);
  return piece;
}

/// Body b's piece: its scene of one body's, with the sides of the contact parts against it.
std::optional<BoxPiece> body_piece(const Scene& scene, std::size_t b, int rank, int size) {
  std::vector<BoundarySelector> against;
  for (const SceneContact& c : contact_parts(scene))
    if (c.against && c.against_body == scene.bodies[b].name) against.push_back(*c.against);
  return box_piece_of(body_scene(scene, b), against, rank, size);
}

/// Whether the scene of one body `one`'s mesh is made or read as lists (MeshLists) of which a
/// process makes its piece around any vertices: Voronoi cells on its rectangle or box, a mesh in
/// its polygon, or a file each process reads its piece of (reads_pieces).
bool makes_lists(const Scene& one) {
  const SceneMesh& m = one.mesh;
  if (!m.file.empty()) return reads_pieces(one);
  return m.generator == "voronoi" || !m.polygon.empty();
}

/// The mesh file of the scene of one body `one` (reads_pieces) as lists.
template <int dim>
MeshLists<MeshOf<dim>> file_lists(const Scene& one) {
  if constexpr (dim == 2) {
    if (to_lower(one.mesh.file.extension().string()) == ".poly2d") return read_poly2d_lists(one.mesh.file);
    return read_gmsh_lists(one.mesh.file);
  } else {
    return read_gmsh3d_lists(one.mesh.file);
  }
}

/// require_route_memory of the mesh file of the scene of one body `one`, from its piece `sides`
/// along its boundary, before any other piece is made: the whole mesh's vertices and cells, and
/// in a solid the vertices of its boundary faces counted as its contact nodes (as many as any
/// contact part can hold).
void require_file_piece_memory(const Scene& one, const MeshPieceRead<Mesh>& sides) {
  detail::require_file_memory(
      one, estimate_memory(sides.mesh.num_vertices(), sides.whole_cells, sides.cell_vertices, sides.cell_vertices_squared),
      sides.largest_cell);
}
void require_file_piece_memory(const Scene& one, const MeshPieceRead<Mesh3D>& sides) {
  const Mesh3D& m = sides.mesh;
  std::set<int> boundary;
  for (int f = 0; f < m.num_faces(); ++f)
    if (m.face(f).outer < 0 && !std::binary_search(sides.cut_facets.begin(), sides.cut_facets.end(), f))
      boundary.insert(m.face(f).vertices.begin(), m.face(f).vertices.end());
  const MemoryEstimate condensed = estimate_memory_3d(m.num_vertices(), static_cast<double>(boundary.size()));
  detail::require_route_memory(one, condensed,
                               one.mesh.file.string() + ": " + detail::count_text(m.num_vertices()) + " vertices, " +
                                   detail::count_text(static_cast<double>(boundary.size())) + " on its boundary",
                               one.where("mesh.file"));
}

/// The points of the scene's supports, whose vertices' cells every piece holds.
std::vector<std::array<double, 3>> held_points(const Scene& scene) {
  std::vector<std::array<double, 3>> held = scene.clamped.points;
  for (const SceneDirichlet& d : scene.dirichlet) held.insert(held.end(), d.boundary.points.begin(), d.boundary.points.end());
  return held;
}

/// The piece of a scene of one body's generated box.
template <int dim>
MeshOf<dim> box_mesh_piece(const Scene& scene, const BoxPiece& piece) {
  return detail::generated_mesh(scene, [&] {
    if constexpr (dim == 2) {
      if (is_polar(scene)) {
        const auto [radii, angles] = detail::polar_lists(scene);
        return make_polar_piece(Vec2(scene.mesh.center[0], scene.mesh.center[1]), radii, angles, piece);
      }
      const auto& d = scene.mesh.domain;
      return make_mesh_piece(scene.mesh.generator, scene.mesh.cells(), Rectangle{d[0], d[1], d[2], d[3]}, piece,
                             static_cast<std::uint64_t>(scene.mesh.seed));
    } else {
      const auto& b = scene.mesh.box;
      return make_mesh3d_piece(scene.mesh.generator, scene.mesh.cells3(), Box{b[0], b[1], b[2], b[3], b[4], b[5]}, piece);
    }
  });
}

}  // namespace

std::optional<BoxPiece> scene_piece(const Scene& scene, int rank, int size) {
  if (!scene.bodies.empty() || scene.adapt) return std::nullopt;
  return box_piece_of(scene, {}, rank, size, true);
}

namespace {

/// The number of cells of the generated mesh of the scene of one body (a box or a polar grid).
int generated_cells(const Scene& scene) {
  const std::string& g = scene.mesh.generator;
  if (scene.dimension() == 3) {
    const GridSize3 n = scene.mesh.cells3();
    return n.nx * n.ny * n.nz * cells_per_box(g);
  }
  if (is_polar(scene)) {
    const auto [radii, angles] = detail::polar_lists(scene);
    return static_cast<int>((radii.size() - 1) * (angles.size() - 1));
  }
  const GridSize n = scene.mesh.cells();
  return n.nx * n.ny * cells_per_box(g);
}

}  // namespace

PieceOfMesh scene_piece_of_mesh(const Scene& scene, const BoxPiece& piece) {
  PieceOfMesh out;
  out.vertices = VertexShare{piece.first_vertex, piece.end_vertex, {}};
  const std::string& g = scene.mesh.generator;
  if (scene.dimension() == 3) out.cells = piece_cells(g, scene.mesh.cells3(), piece);
  else if (is_polar(scene)) {
    const auto [radii, angles] = detail::polar_lists(scene);
    out.cells = polar_piece_cells(radii, angles, piece);
  } else
    out.cells = piece_cells(g, scene.mesh.cells(), piece);
  out.whole_cells = generated_cells(scene);
  return out;
}

template <>
std::unique_ptr<BasicBuiltProblem<2>> build_problem_piece<2>(const Scene& scene, const BoxPiece& piece,
                                                             const RowDistribution& processes) {
  Mesh mesh = box_mesh_piece<2>(scene, piece);
  const std::vector<int> cut = grid_cut_facets(mesh, grid_vertices_of(scene));
  const detail::SupportsAcross across{&processes, VertexShare{piece.first_vertex, piece.end_vertex, {}}.mask(mesh.num_vertices())};
  auto built = detail::built_plane_on(scene, std::move(mesh), true, false, cut, &across);
  built->problem.elasticity.piece_bodies = {{0, built->mesh.num_vertices()}, {generated_cells(scene)}};
  return built;
}

template <>
std::unique_ptr<BasicBuiltProblem<3>> build_problem_piece<3>(const Scene& scene, const BoxPiece& piece,
                                                             const RowDistribution& processes) {
  detail::require_dimension<3>(scene);
  Mesh3D mesh = box_mesh_piece<3>(scene, piece);
  const std::vector<int> cut = grid_cut_facets(mesh, grid_vertices_of(scene));
  const detail::SupportsAcross across{&processes, VertexShare{piece.first_vertex, piece.end_vertex, {}}.mask(mesh.num_vertices())};
  auto built = detail::built_solid(scene, std::move(mesh), true, cut, &across);
  built->problem.elasticity.piece_bodies = {{0, built->mesh.num_vertices()}, {generated_cells(scene)}};
  return built;
}

bool makes_body_pieces(const Scene& scene) {
  if (scene.bodies.empty() || scene.adapt) return false;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (!body_piece(scene, b, 0, 1) && !makes_lists(body_scene(scene, b))) return false;
  return true;
}

namespace {

/// The problem `held` (on a mesh made whole, or on a process's piece of it that holds the cells
/// of every facet its selectors may pick) on the piece of its mesh around the vertices `around`
/// flags (cut_problem_piece's rule), `held` given back: `cells` the piece's cells, increasing
/// numbers of the cells of held->mesh. `body_cells`: each body's number of cells in the whole
/// mesh (PieceBodies::cells). `points`: the vertices the supports hold at points, whose cells are
/// kept; none given, every vertex a support lists (its points', on a piece whose supports were
/// not completed across the processes).
template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> keep_around(std::unique_ptr<BasicBuiltProblem<dim>> held, std::vector<char> around,
                                                    std::vector<int> body_cells, std::vector<int>& cells,
                                                    const std::vector<int>* points = nullptr) {
  const MeshOf<dim>& mesh = held->mesh;
  const BasicContactProblem<dim>& problem = held->problem;
  // a mesh whose every body (every part of a joined mesh, or the mesh) is one connected piece by
  // the rigid motions' rule: the piece holds each in one too (piece_cells_around), keeps the cells
  // of the contact's facets alone, and of the supports and loads the facets among its cells, each
  // support holding every vertex it holds of the mesh
  std::vector<int> bodies = body_vertex_starts(held->bodies, mesh.num_vertices());
  const bool each_body_one = count_pieces(mesh) == static_cast<int>(bodies.size()) - 1;
  std::vector<int> facets;
  if (!each_body_one) {
    for (const auto& d : problem.elasticity.dirichlet) facets.insert(facets.end(), d.facets.begin(), d.facets.end());
    for (const auto& t : problem.elasticity.tractions) facets.insert(facets.end(), t.facets.begin(), t.facets.end());
  }
  for (const auto& p : problem.parts) {
    facets.insert(facets.end(), p.facets.begin(), p.facets.end());
    facets.insert(facets.end(), p.against.begin(), p.against.end());
  }
  // the cells around the process's vertices and around the vertices supported alone (a body's
  // supports, when they are points, are in every piece of it)
  if (points)
    for (int v : *points) around[static_cast<std::size_t>(v)] = 1;
  else
    for (const auto& d : problem.elasticity.dirichlet)
      for (int v : d.vertices) around[static_cast<std::size_t>(v)] = 1;
  cells = piece_cells_around(mesh, around, facets);
  std::vector<std::vector<int>> supported;  // each support's vertices of the mesh
  if (each_body_one)
    for (const auto& d : problem.elasticity.dirichlet) {
      std::vector<int> vertices = d.held_vertices(mesh);
      std::sort(vertices.begin(), vertices.end());
      vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
      supported.push_back(std::move(vertices));
    }
  // the problem on the piece: its facets renumbered, the rest (numbered by vertices, or
  // functions of the point) as it is
  auto out = std::make_unique<BasicBuiltProblem<dim>>();
  std::vector<int> facet_of;
  out->mesh = cut_mesh_piece(mesh, cells, &facet_of);
  const auto renumber = [&](std::vector<int>& ids) {
    for (int& f : ids) {
      f = facet_of[static_cast<std::size_t>(f)];
      if (f < 0) throw InternalError("cut_problem_piece: a facet of the problem lies outside the piece");
    }
  };
  const auto among = [&](std::vector<int>& ids) {  // those the piece holds, renumbered
    std::erase_if(ids, [&](int f) { return facet_of[static_cast<std::size_t>(f)] < 0; });
    renumber(ids);
  };
  out->problem = std::move(held->problem);
  out->problem.elasticity.mesh = &out->mesh;
  if (each_body_one) out->problem.elasticity.piece_bodies = {std::move(bodies), std::move(body_cells)};
  for (std::size_t k = 0; k < out->problem.elasticity.dirichlet.size(); ++k) {
    auto& d = out->problem.elasticity.dirichlet[k];
    if (!each_body_one) {
      renumber(d.facets);
      continue;
    }
    among(d.facets);
    d.vertices.insert(d.vertices.end(), supported[k].begin(), supported[k].end());
  }
  for (auto& t : out->problem.elasticity.tractions) each_body_one ? among(t.facets) : renumber(t.facets);
  for (auto& p : out->problem.parts) {
    renumber(p.facets);
    renumber(p.against);
  }
  out->has_contact = held->has_contact;
  out->warnings = std::move(held->warnings);
  out->bodies = std::move(held->bodies);
  for (BodyRange& b : out->bodies) {  // the piece's cells of each body, in the mesh's order
    const auto first = std::lower_bound(cells.begin(), cells.end(), b.first_cell);
    const auto end = std::lower_bound(cells.begin(), cells.end(), b.first_cell + b.cells);
    b.first_cell = static_cast<int>(first - cells.begin());
    b.cells = static_cast<int>(end - first);
  }
  held.reset();
  return out;
}

/// The vertices each process r owns among a body's generated ones: owned(r), one flag each.
using OwnedOf = std::function<std::vector<char>(int)>;

/// How a process makes its piece of a body's mesh: of its generated box (BoxPiece) or of the
/// lists its generator makes or its file holds (MeshLists), around the vertices it owns. Across
/// processes the lists are made by the first process alone, which sends every process its
/// pieces (ListsOfFirst, piece_of_lists_by_first).
template <int dim>
struct BodyPieceMaker {
  std::optional<BoxPiece> box;
  MeshLists<MeshOf<dim>> lists;  // made by this process, without processes
  std::optional<ListsOfFirst<MeshOf<dim>>> of_first;  // across processes
  std::optional<MeshLists<MeshOf<dim>>> firsts;       // the first process's lists
  const RowDistribution* processes = nullptr;
  int rank = 0;
  std::vector<std::array<double, 3>> held;  // of the lists' piece
  int vertices = 0;                         // the body's generated ones (of lists of the first, once its sides are made)

  /// `processes`: across processes, among which a Voronoi generator's Lloyd iterations are split
  /// and of which the first makes the lists (collective); else process `rank` makes them.
  BodyPieceMaker(const Scene& scene, std::size_t b, int rank, const RowDistribution* processes)
      : processes(processes), rank(rank) {
    const Scene one = body_scene(scene, b);
    held = held_points(one);
    if (!one.mesh.file.empty()) {  // its memory checked once its piece along its sides is read
      if (processes) {
        of_first = ListsOfFirst<MeshOf<dim>>{[one] { return file_lists<dim>(one); }, {}};
        return;
      }
      lists = file_lists<dim>(one);
      vertices = lists.vertices;
      return;
    }
    detail::require_generated_memory(one);
    box = body_piece(scene, b, 0, 1);
    if (box) {
      vertices = box->end_vertex;
      return;
    }
    const auto seed = static_cast<std::uint64_t>(one.mesh.seed);
    if (processes) {
      ListsOfFirst<MeshOf<dim>> made = detail::generated_mesh(one, [&] {
        if constexpr (dim == 2) {
          if (!one.mesh.polygon.empty())
            return mesh_lists_of_first(one.mesh.generator, one.mesh.n, detail::polygon_domain(one), seed);
          const auto& d = one.mesh.domain;
          return voronoi_lists_of_first(one.mesh.cells(), Rectangle{d[0], d[1], d[2], d[3]}, *processes, {.seed = seed});
        } else {
          const auto& x = one.mesh.box;
          return voronoi3d_lists_of_first(one.mesh.cells3(), Box{x[0], x[1], x[2], x[3], x[4], x[5]}, *processes,
                                          {.seed = seed});
        }
      });
      // the generator's errors and the whole mesh's defect, met by the first, named as the scene's mesh's
      made.make = [one, make = std::move(made.make)] {
        MeshLists<MeshOf<dim>> lists = detail::generated_mesh(one, make);
        lists.name_defect = [one, name = std::move(lists.name_defect)] {
          detail::generated_mesh(one, [&] {
            name();
            return 0;
          });
        };
        return lists;
      };
      of_first = std::move(made);
      return;
    }
    lists = detail::generated_mesh(one, [&] {
      if constexpr (dim == 2) {
        if (!one.mesh.polygon.empty()) return mesh_lists(one.mesh.generator, one.mesh.n, detail::polygon_domain(one), seed);
        const auto& d = one.mesh.domain;
        return voronoi_lists(one.mesh.cells(), Rectangle{d[0], d[1], d[2], d[3]}, VoronoiOptions{.seed = seed});
      } else {
        const auto& x = one.mesh.box;
        return voronoi3d_lists(one.mesh.cells3(), Box{x[0], x[1], x[2], x[3], x[4], x[5]}, VoronoiOptions{.seed = seed});
      }
    });
    vertices = lists.vertices;
  }

  /// The piece around the generated vertices `owned(rank)` flags, and the cells around each
  /// vertex a support at a point holds (none given: the cells along the body's sides alone, which
  /// tell the body's number of generated vertices where the first process makes the lists), with
  /// the facets where it meets the rest of the body; where it lies in the body's whole mesh into
  /// `where` when given. Collective across processes.
  detail::BodyMesh<dim> piece(const Scene& one, const OwnedOf* owned, PieceOfMesh* where) {
    if (box) {
      BoxPiece mine = *box;
      mine.first_vertex = mine.end_vertex = 0;
      if (owned) mine.owned = (*owned)(rank);
      else mine.held.clear();
      if (where) *where = scene_piece_of_mesh(one, mine);
      MeshOf<dim> mesh = box_mesh_piece<dim>(one, mine);
      std::vector<int> cut = grid_cut_facets(mesh, grid_vertices_of(one));
      return in_regions({std::move(mesh), std::move(cut)}, one);
    }
    const auto make = [&] {
      if (of_first) return piece_of_lists_by_first(*processes, *of_first, firsts, owned ? *owned : OwnedOf{}, held);
      if (owned) return lists.piece((*owned)(rank), held);
      return lists.piece(std::vector<char>(static_cast<std::size_t>(vertices), 0), {});
    };
    const bool file = !one.mesh.file.empty();  // a file's errors name it, not a generator
    MeshPieceRead<MeshOf<dim>> made = file || of_first ? make() : detail::generated_mesh(one, make);
    if (!owned && of_first) vertices = made.mesh.num_vertices();
    if (file && !owned) require_file_piece_memory(one, made);
    if (where) {
      where->cells = std::move(made.cells);
      where->whole_cells = made.whole_cells;
    }
    return in_regions({std::move(made.mesh), std::move(made.cut_facets)}, one);
  }

  /// A piece of the mesh of the scene of one body `one`, the whole mesh's regions counted
  /// (region_count: every piece holds a cell of each of its own regions) and its cells put into
  /// the regions of its region boxes (in the plane).
  static detail::BodyMesh<dim> in_regions(detail::BodyMesh<dim> piece, const Scene& one) {
    piece.regions = detail::region_count(one, piece.mesh.regions());
    if constexpr (dim == 2) detail::apply_region_boxes(one, piece.mesh);
    return piece;
  }
};

}  // namespace

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> build_bodies_piece(const Scene& scene, int rank, int size, PieceOfMesh& where,
                                                           const RowDistribution* processes) {
  detail::require_dimension<dim>(scene);
  if (!makes_body_pieces(scene))
    throw InputError("build_bodies_piece: the scene's bodies are not made in pieces (makes_body_pieces)", scene.where("body"));
  const std::size_t bodies = scene.bodies.size();
  std::vector<BodyPieceMaker<dim>> makers;
  for (std::size_t b = 0; b < bodies; ++b) makers.emplace_back(scene, b, rank, processes);
  // every vertex of the joined mesh, from the bodies' cells along their sides alone, matched
  // and joined (a surface's worth): where each body's vertices lie, and the Hilbert order of
  // them all that the processes share, as they share a mesh made whole
  std::vector<int> first_vertex{0};
  {
    const std::vector<detail::BodyMesh<dim>> sides =
        detail::matched_meshes<dim>(scene, [&](const Scene& one, std::size_t b) {
          return makers[b].piece(one, nullptr, nullptr);
        });
    std::vector<const MeshOf<dim>*> meshes;
    std::vector<std::string> names;
    for (std::size_t b = 0; b < bodies; ++b) {
      first_vertex.push_back(first_vertex.back() + sides[b].mesh.num_vertices());
      meshes.push_back(&sides[b].mesh);
      names.push_back(scene.bodies[b].name);
    }
    where = PieceOfMesh{};
    where.vertices.order = hilbert_vertex_order(join_meshes(meshes, names).mesh);
  }
  std::tie(where.vertices.first, where.vertices.end) = vertex_share(first_vertex.back(), rank, size);
  const std::vector<char> mine = where.vertices.mask(first_vertex.back());
  std::vector<PieceOfMesh> in_body(bodies);
  auto out = detail::built_bodies<dim>(scene, [&](const Scene& one, std::size_t b) {
    // each process's vertices among body b's generated ones
    const OwnedOf owned = [&, b](int r) {
      std::vector<char> flags(static_cast<std::size_t>(makers[b].vertices), 0);
      const auto [from, to] = vertex_share(first_vertex.back(), r, size);
      for (auto k = from; k < to; ++k)
        if (const int v = where.vertices.order[static_cast<std::size_t>(k)] - first_vertex[b]; v >= 0 && v < makers[b].vertices)
          flags[static_cast<std::size_t>(v)] = 1;
      return flags;
    };
    return makers[b].piece(one, &owned, &in_body[b]);
  });
  for (std::size_t b = 0; b < bodies; ++b) {  // each body's cells follow the bodies' before it
    if (out->bodies[b].first_vertex != first_vertex[b] || out->bodies[b].vertices != first_vertex[b + 1] - first_vertex[b])
      throw InternalError("build_bodies_piece: body " + std::to_string(b) + "'s piece was matched to other vertices");
    for (int c : in_body[b].cells) where.cells.push_back(where.whole_cells + c);
    where.whole_cells += in_body[b].whole_cells;
  }
  // kept on the contact's cells alone where each body is one piece (keep_around)
  std::vector<int> kept, body_cells;
  for (const PieceOfMesh& body : in_body) body_cells.push_back(body.whole_cells);
  out = keep_around<dim>(std::move(out), mine, std::move(body_cells), kept);
  for (int& c : kept) c = where.cells[static_cast<std::size_t>(c)];
  where.cells = std::move(kept);
  return out;
}

template std::unique_ptr<BasicBuiltProblem<2>> build_bodies_piece<2>(const Scene&, int, int, PieceOfMesh&,
                                                                     const RowDistribution*);
template std::unique_ptr<BasicBuiltProblem<3>> build_bodies_piece<3>(const Scene&, int, int, PieceOfMesh&,
                                                                     const RowDistribution*);

bool reads_pieces(const Scene& scene) {
  const SceneMesh& m = scene.mesh;
  if (!scene.bodies.empty() || m.file.empty() || scene.adapt) return false;
  const std::string ext = to_lower(m.file.extension().string());
  return ext == ".msh" || (ext == ".poly2d" && scene.dimension() == 2);
}

namespace {

/// The scene's problem on the piece `read` (a file's or a mesh made as lists), no selector picking
/// the facets where it meets the others, then on the piece of it that keep_around keeps (the
/// cells of every boundary facet `read` holds are those any selector may pick; of a mesh of one
/// body the contact's alone are kept); where it lies in the whole mesh into `where` (its share
/// and cells taken). A piece that holds of the boundary the contact's cells alone (read.picked,
/// by contact_pick) has its supports and loads completed across `processes` (SupportsAcross;
/// collective).
template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> built_on_piece(const Scene& scene, MeshPieceRead<MeshOf<dim>>& read,
                                                       PieceOfMesh& where, const RowDistribution* processes = nullptr) {
  where.vertices = VertexShare{read.first, read.end, std::move(read.order)};
  where.whole_cells = read.whole_cells;
  const int vertices = read.mesh.num_vertices();
  std::vector<char> owned = where.vertices.mask(vertices);
  std::optional<detail::SupportsAcross> across;
  std::vector<int> points;  // of a completed piece: the vertices its supports hold at points
  if (read.picked) {
    if (processes == nullptr) throw InternalError("a piece holding the contact's boundary alone, posed without its processes");
    across = detail::SupportsAcross{processes, owned};
    for (const auto& q : held_points(scene))
      if (const int v = nearest_point<dim>(read.mesh.vertices(), Eigen::Map<const Eigen::Vector3d>(q.data()).head<dim>()).first; v >= 0)
        points.push_back(v);
  }
  const detail::SupportsAcross* completed = across ? &*across : nullptr;
  std::unique_ptr<BasicBuiltProblem<dim>> held;
  if constexpr (dim == 2) held = detail::built_plane_on(scene, std::move(read.mesh), true, false, read.cut_facets, completed);
  else held = detail::built_solid(scene, std::move(read.mesh), false, read.cut_facets, completed);
  across.reset();
  std::vector<int> kept;
  auto out = keep_around<dim>(std::move(held), std::move(owned), {read.whole_cells}, kept, read.picked ? &points : nullptr);
  where.cells.resize(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) where.cells[k] = read.cells[static_cast<std::size_t>(kept[k])];
  return out;
}

}  // namespace

namespace {

/// What every piece of the scene's mesh of one body holds of its boundary (BoundaryPick): the
/// facets of its contact parts, as the scene's selectors pick them on `sides`, which holds every
/// facet they may pick (their errors are then the whole mesh's).
template <int dim>
BoundaryPick<MeshOf<dim>> contact_pick(const Scene& scene) {
  return [&scene](MeshPieceRead<MeshOf<dim>>&& sides) {
    std::unique_ptr<BasicBuiltProblem<dim>> on;
    if constexpr (dim == 2) on = detail::built_plane_on(scene, std::move(sides.mesh), false, false, sides.cut_facets);
    else on = detail::built_solid(scene, std::move(sides.mesh), false, sides.cut_facets);
    std::vector<int> facets;
    for (const auto& p : on->problem.parts) {
      facets.insert(facets.end(), p.facets.begin(), p.facets.end());
      facets.insert(facets.end(), p.against.begin(), p.against.end());
    }
    return facet_keys(on->mesh, facets);
  };
}

/// read_problem_piece on the piece `read(path, held)` reads of the scene's file (a Gmsh file,
/// or in the plane a .poly2d file: `poly2d`); `processes` as built_on_piece's.
template <int dim, class Read>
std::unique_ptr<BasicBuiltProblem<dim>> problem_on_read_piece(const Scene& scene, PieceOfMesh& where, Read&& read,
                                                              const RowDistribution* processes = nullptr) {
  detail::require_dimension<dim>(scene);
  const std::vector<std::array<double, 3>> held = held_points(scene);
  const bool poly2d = to_lower(scene.mesh.file.extension().string()) == ".poly2d";
  MeshPieceRead<MeshOf<dim>> piece = read(scene.mesh.file, held, poly2d);
  if constexpr (dim == 2)
    detail::require_file_memory(scene,
                                estimate_memory(piece.mesh.num_vertices(), piece.whole_cells, piece.cell_vertices,
                                                piece.cell_vertices_squared),
                                piece.largest_cell);
  return built_on_piece<dim>(scene, piece, where, processes);
}

}  // namespace

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> read_problem_piece(const Scene& scene, int rank, int size, PieceOfMesh& where) {
  return problem_on_read_piece<dim>(scene, where, [&](const std::filesystem::path& file, HeldPoints held, bool poly2d) {
    if constexpr (dim == 2) return poly2d ? read_poly2d_piece(file, rank, size, held) : read_gmsh_piece(file, rank, size, held);
    else return read_gmsh3d_piece(file, rank, size, held);
  });
}

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> read_problem_piece(const Scene& scene, const RowDistribution& processes,
                                                           PieceOfMesh& where) {
  const BoundaryPick<MeshOf<dim>> pick = contact_pick<dim>(scene);
  return problem_on_read_piece<dim>(
      scene, where,
      [&](const std::filesystem::path& file, HeldPoints held, bool poly2d) {
        if constexpr (dim == 2)
          return poly2d ? read_poly2d_piece(file, processes, held, pick) : read_gmsh_piece(file, processes, held, pick);
        else
          return read_gmsh3d_piece(file, processes, held, pick);
      },
      &processes);
}

template std::unique_ptr<BasicBuiltProblem<2>> read_problem_piece<2>(const Scene&, int, int, PieceOfMesh&);
template std::unique_ptr<BasicBuiltProblem<3>> read_problem_piece<3>(const Scene&, int, int, PieceOfMesh&);
template std::unique_ptr<BasicBuiltProblem<2>> read_problem_piece<2>(const Scene&, const RowDistribution&, PieceOfMesh&);
template std::unique_ptr<BasicBuiltProblem<3>> read_problem_piece<3>(const Scene&, const RowDistribution&, PieceOfMesh&);

bool makes_voronoi_pieces(const Scene& scene) {
  const SceneMesh& m = scene.mesh;
  return scene.bodies.empty() && !scene.adapt && m.file.empty() && m.generator == "voronoi" && m.polygon.empty();
}

namespace {

/// An error met where the mesh's generator did not meet it, carried past generated_mesh, which
/// names the generator's errors as the scene's mesh's: the scene's contact picked on the first
/// process (named as on the whole mesh), or another process's word that the first stopped.
struct NotTheGenerators : std::runtime_error {
  NotTheGenerators(const char* what, std::exception_ptr error) : std::runtime_error(what), error(std::move(error)) {}
  std::exception_ptr error;
};

/// make(pick), which makes this process's piece of the scene's generated mesh, the first process
/// making every piece and `pick` its contact_pick (collective over `processes`): the generator's
/// errors named as generated_mesh names them, the pick's as the scene's selectors name them on
/// the whole mesh, and on the others "process 0 stopped: <its error>".
template <int dim, class Make>
MeshPieceRead<MeshOf<dim>> piece_generated_by_first(const Scene& scene, Make&& make) {
  const BoundaryPick<MeshOf<dim>> contact = contact_pick<dim>(scene);
  const BoundaryPick<MeshOf<dim>> pick = [&](MeshPieceRead<MeshOf<dim>>&& sides) {
    try {
      return contact(std::move(sides));
    } catch (const std::exception& e) {
      throw NotTheGenerators(e.what(), std::current_exception());
    }
  };
  try {
    return detail::generated_mesh(scene, [&] {
      try {
        return make(pick);
      } catch (const InputError& e) {
        if (e.detail().starts_with("process 0 stopped: ")) throw NotTheGenerators(e.what(), std::current_exception());
        throw;
      }
    });
  } catch (const NotTheGenerators& e) {
    std::rethrow_exception(e.error);
  }
}

}  // namespace

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> voronoi_problem_piece(const Scene& scene, const RowDistribution& processes,
                                                              PieceOfMesh& where) {
  detail::require_dimension<dim>(scene);
  detail::require_generated_memory(scene);
  VoronoiOptions options;
  options.seed = static_cast<std::uint64_t>(scene.mesh.seed);
  const std::vector<std::array<double, 3>> held = held_points(scene);
  MeshPieceRead<MeshOf<dim>> made = piece_generated_by_first<dim>(scene, [&](const BoundaryPick<MeshOf<dim>>& pick) {
    if constexpr (dim == 2) {
      const auto& d = scene.mesh.domain;
      return make_voronoi_piece(scene.mesh.cells(), Rectangle{d[0], d[1], d[2], d[3]}, processes, options, held, pick);
    } else {
      const auto& b = scene.mesh.box;
      return make_voronoi3d_piece(scene.mesh.cells3(), Box{b[0], b[1], b[2], b[3], b[4], b[5]}, processes, options,
                                  held, pick);
    }
  });
  return built_on_piece<dim>(scene, made, where, &processes);
}

template std::unique_ptr<BasicBuiltProblem<2>> voronoi_problem_piece<2>(const Scene&, const RowDistribution&, PieceOfMesh&);
template std::unique_ptr<BasicBuiltProblem<3>> voronoi_problem_piece<3>(const Scene&, const RowDistribution&, PieceOfMesh&);

bool makes_polygon_pieces(const Scene& scene) {
  const SceneMesh& m = scene.mesh;
  return scene.bodies.empty() && !scene.adapt && m.file.empty() && !m.polygon.empty();
}

std::unique_ptr<BuiltProblem> polygon_problem_piece(const Scene& scene, int rank, int size, PieceOfMesh& where) {
  detail::require_dimension<2>(scene);
  detail::require_generated_memory(scene);
  const std::vector<std::array<double, 3>> held = held_points(scene);
  MeshPieceRead<Mesh> made = detail::generated_mesh(scene, [&] {
    return make_mesh_piece(scene.mesh.generator, scene.mesh.n, detail::polygon_domain(scene),
                           static_cast<std::uint64_t>(scene.mesh.seed), rank, size, held);
  });
  return built_on_piece<2>(scene, made, where);
}

std::unique_ptr<BuiltProblem> polygon_problem_piece(const Scene& scene, const RowDistribution& processes,
                                                    PieceOfMesh& where) {
  detail::require_dimension<2>(scene);
  detail::require_generated_memory(scene);
  const std::vector<std::array<double, 3>> held = held_points(scene);
  MeshPieceRead<Mesh> made = piece_generated_by_first<2>(scene, [&](const BoundaryPick<Mesh>& pick) {
    return make_mesh_piece(scene.mesh.generator, scene.mesh.n, detail::polygon_domain(scene),
                           static_cast<std::uint64_t>(scene.mesh.seed), processes, held, pick);
  });
  return built_on_piece<2>(scene, made, where, &processes);
}

void check_regions_of_pieces(const Scene& scene, const std::vector<int>& regions) {
  detail::check_regions_present(scene, std::set<int>(regions.begin(), regions.end()), true);
}

bool cuts_pieces(const Scene& scene) {
  return !scene.adapt && !scene_piece(scene, 0, 1) && !reads_pieces(scene) && !makes_voronoi_pieces(scene) &&
         !makes_polygon_pieces(scene) && !makes_body_pieces(scene);
}

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> cut_problem_piece(std::unique_ptr<BasicBuiltProblem<dim>> whole, int rank, int size,
                                                          PieceOfMesh& where) {
  const int vertices = whole->mesh.num_vertices();
  where.vertices.order = hilbert_vertex_order(whole->mesh);
  std::tie(where.vertices.first, where.vertices.end) = vertex_share(vertices, rank, size);
  where.whole_cells = whole->mesh.num_cells();
  std::vector<int> body_cells;
  for (const BodyRange& body : whole->bodies) body_cells.push_back(body.cells);
  if (whole->bodies.empty()) body_cells.push_back(where.whole_cells);
  return keep_around<dim>(std::move(whole), where.vertices.mask(vertices), std::move(body_cells), where.cells);
}

template std::unique_ptr<BasicBuiltProblem<2>> cut_problem_piece<2>(std::unique_ptr<BasicBuiltProblem<2>>, int, int,
                                                                    PieceOfMesh&);
template std::unique_ptr<BasicBuiltProblem<3>> cut_problem_piece<3>(std::unique_ptr<BasicBuiltProblem<3>>, int, int,
                                                                    PieceOfMesh&);

}  // namespace hemivem
