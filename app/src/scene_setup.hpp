// What solve_scene and solve_scene_path do before they solve (private to hemivem::app).
#pragma once

#include <algorithm>
#include <any>
#include <array>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <hemivem/contact/pose_share.hpp>
#include <hemivem/every_process.hpp>
#include <hemivem/estimate/estimate_pieces.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/scene/scene_pieces.hpp>
#include <hemivem/mesh/mesh_record.hpp>
#include <hemivem/mesh/vertex_order.hpp>

#include "bodies.hpp"
#include "output_run.hpp"
#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/sparse_factorization.hpp>

namespace hemivem::app::detail {

/// The engines a scene names and what a solve records about them (SceneSolve, SceneSolve3D).
struct SceneEngines {
  std::unique_ptr<SparseFactorization> factorization;  ///< null on the full-space route
  std::unique_ptr<KrylovSolver> krylov;                ///< the full-space route's engine (a Krylov engine named)
  std::unique_ptr<NonsmoothMinimizer> minimizer;
  std::string linear;            ///< the linear engine's name
  std::string minimizer_name;    ///< the minimizer's (the first engine of a global search)
  nlohmann::json search;         ///< search_json
  bool holds_results = true;     ///< false on the ranks > 0 of mumps-mpi
  int processes = 1;
  /// Across processes, the memory checks count every process (MemoryOfProcesses) while the
  /// engines live.
  std::unique_ptr<MemoryOfProcesses> memory_of_processes;
  MinimizerOptions options;      ///< the scene's tolerance and iteration limit, with `callback`
  /// On the full-space route across processes, where this process's piece of the scene's mesh
  /// lies when it made only its piece (build_scene_problem); none when it made the whole mesh.
  std::optional<PieceOfMesh> piece;
  /// The coarser grids a static solve on the scene's own mesh starts from (grid_sequence_levels,
  /// checked when the engines are made).
  int grid_levels = 0;
  /// Whether the problem was built on the scene's own mesh (build_scene_problem), not on a mesh
  /// the caller gave: only then does a grid sequence run.
  bool scene_mesh = false;
  /// The caller writes the results to the output folder it named (SceneSolveOptions::out), as
  /// the command does: a static solve on pieces then writes its solution in pieces (each
  /// process its piece of solution.pvtu, BasicSceneSolve::share), and a process that does not
  /// write the other results keeps its piece of the mesh after the solve (its piece of
  /// solution.pvtu needs no more). Otherwise every process makes the whole mesh of the results
  /// it holds, and the first writes solution.vtu.
  bool writes_to_folder = false;
  /// Told each coarser grid's record as it is solved (SceneSolveOptions::on_coarser_grid).
  std::function<void(const nlohmann::json&)> on_coarser_grid;
  /// Where each process keeps its piece of a mesh the caller gave (build_given_problem), the
  /// whole problem made again after the solve: a WholeProblem<dim>. Empty otherwise.
  std::any whole_problem;
};

/// The whole problem on a mesh the caller gave, made again (SceneEngines::whole_problem).
template <int dim>
using WholeProblem = std::function<std::unique_ptr<BasicBuiltProblem<dim>>()>;

/// The problem of `scene` on a mesh the caller gave (an adaptive solve's refined mesh), into
/// s.built (build_problem(scene, mesh), a plane's with its region boxes where `region_boxes`): on
/// the full-space route across processes, for a mesh of one body, the piece each process keeps of
/// it for the solve (cut_problem_piece; e.piece, s.mesh_pieces, s.whole_cells) and a record of
/// the whole mesh (MeshRecord), the whole given back; the whole problem is made again from the
/// record after the solve (e.whole_problem, make_results_mesh_whole). The whole otherwise.
template <int dim, class Solved>
void build_given_problem(const Scene& scene, SceneEngines& e, Solved& s, MeshOf<dim> mesh, bool region_boxes) {
  const auto build = [&scene](MeshOf<dim> m, bool boxes) {
    if constexpr (dim == 2) {
      return build_problem(scene, std::move(m), boxes);
    } else {
      (void)boxes;  // a solid has no region boxes
      return build_problem(scene, std::move(m));
    }
  };
  std::unique_ptr<BasicBuiltProblem<dim>> whole = build(std::move(mesh), region_boxes);
  if (!(e.krylov && e.processes > 1) || !whole->bodies.empty()) {
    s.built = std::move(whole);
    return;
  }
  // the regions the boxes gave are recorded: the whole is made again without them
  auto record = std::make_shared<const MeshRecord<dim>>(whole->mesh);
  const ProcessWorld world = krylov_world();
  PieceOfMesh where;
  s.built = on_every_process(*process_rows(),
                             [&] { return cut_problem_piece<dim>(std::move(whole), world.rank, world.size, where); });
  s.mesh_pieces = world.size;
  s.whole_cells = where.whole_cells;
  e.piece = std::move(where);
  e.whole_problem = WholeProblem<dim>([build, record] { return build(record->make(), false); });
}

/// Collective: every region of the scene (of each body, of a scene of several) holds a cell of
/// the whole mesh whose pieces the processes made (check_regions_of_pieces of every piece's
/// region ids, each body's its own: BodyRange::first_region).
template <int dim>
void check_regions_across(const Scene& scene, const BasicBuiltProblem<dim>& piece, const RowDistribution& rows) {
  std::vector<BodyRange> bodies = piece.bodies;
  if (bodies.empty()) bodies.push_back(BodyRange{"", 0, piece.mesh.num_vertices(), 0, piece.mesh.num_cells(), 0});
  std::vector<std::array<int, 2>> mine;  // (body, its region) of each of the piece's cells
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (int c = bodies[b].first_cell; c < bodies[b].first_cell + bodies[b].cells; ++c)
      mine.push_back({static_cast<int>(b), piece.mesh.region(c) - bodies[b].first_region});
  std::sort(mine.begin(), mine.end());
  mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
  Eigen::VectorXd flat(2 * static_cast<Eigen::Index>(mine.size()));
  for (std::size_t k = 0; k < mine.size(); ++k) {
    flat(2 * static_cast<Eigen::Index>(k)) = mine[k][0];
    flat(2 * static_cast<Eigen::Index>(k) + 1) = mine[k][1];
  }
  const Eigen::VectorXd all = rows.all_gather(flat);
  std::vector<std::vector<int>> regions(bodies.size());
  for (Eigen::Index k = 0; k + 1 < all.size(); k += 2)
    regions[static_cast<std::size_t>(all(k))].push_back(static_cast<int>(all(k + 1)));
  if (scene.bodies.empty()) check_regions_of_pieces(scene, regions.front());
  else
    for (std::size_t b = 0; b < bodies.size(); ++b) check_regions_of_pieces(body_scene(scene, b), regions[b]);
}

/// The problem a solve of the scene builds on the scene's own mesh, into s.built: on the
/// full-space route across processes (`e`), the process's piece of the mesh where the scene
/// allows it: a generated box's piece made directly (scene_piece), a mesh file's piece read
/// alone (reads_pieces), a Voronoi mesh's or a polygon's mesh's piece made from its cells' lists
/// (makes_voronoi_pieces, makes_polygon_pieces),
/// each generated body's piece made directly and the pieces matched and
/// joined (makes_body_pieces; an error one process meets in any of these ends every process,
/// and the regions are checked across the processes: check_regions_across), or the piece it
/// keeps of a mesh made whole (cuts_pieces; each process doing its share of the generator's work where it
/// splits it: build_problem); e.piece then says where the piece lies, and s.mesh_pieces and
/// s.whole_cells what it is a piece of. The whole mesh otherwise. Given `out`, the solve
/// writes to that folder (e.writes_to_folder): a path's VTU frames, and a static solve's
/// solution, in pieces.
template <int dim, class Solved>
void build_scene_problem(const Scene& scene, SceneEngines& e, Solved& s, const std::filesystem::path& out = {}) {
  e.scene_mesh = true;
  if (e.krylov && e.processes > 1) {
    const ProcessWorld world = krylov_world();
    if (const std::optional<BoxPiece> piece = scene_piece(scene, world.rank, world.size)) {
      s.mesh_pieces = world.size;
      e.writes_to_folder = !out.empty();
      s.built = on_every_process(*process_rows(), [&] { return build_problem_piece<dim>(scene, *piece, *process_rows()); });
      check_regions_across(scene, *s.built, *process_rows());
      e.piece = scene_piece_of_mesh(scene, *piece);
      s.whole_cells = e.piece->whole_cells;
      return;
    }
    // the first process reads the file, or makes the Voronoi or polygon mesh's cells, and sends each
    // its piece; each makes its piece of its bodies'
    if (reads_pieces(scene) || makes_voronoi_pieces(scene) || makes_polygon_pieces(scene) || makes_body_pieces(scene)) {
      PieceOfMesh where;
      s.built = on_every_process(*process_rows(), [&]() -> std::unique_ptr<BasicBuiltProblem<dim>> {
        if (reads_pieces(scene)) return read_problem_piece<dim>(scene, *process_rows(), where);
        if (makes_voronoi_pieces(scene)) return voronoi_problem_piece<dim>(scene, *process_rows(), where);
        if constexpr (dim == 2)
          if (makes_polygon_pieces(scene)) return polygon_problem_piece(scene, *process_rows(), where);
        return build_bodies_piece<dim>(scene, world.rank, world.size, where, process_rows().get());
      });
      check_regions_across(scene, *s.built, *process_rows());
      s.mesh_pieces = world.size;
      e.writes_to_folder = !out.empty();
      s.whole_cells = where.whole_cells;
      e.piece = std::move(where);
      return;
    }
    // the generator's work split where it splits it
    std::unique_ptr<BasicBuiltProblem<dim>> whole = build_problem<dim>(scene, process_rows().get());
    if (cuts_pieces(scene)) {  // the whole mesh made, each process keeps its piece
      PieceOfMesh where;
      s.built = cut_problem_piece<dim>(std::move(whole), world.rank, world.size, where);
      s.mesh_pieces = world.size;
      e.writes_to_folder = !out.empty();
      s.whole_cells = where.whole_cells;
      e.piece = std::move(where);
      return;
    }
    s.built = std::move(whole);
    return;
  }
  s.built = build_problem<dim>(scene);
}

/// The error estimate of s.solution on s.built->problem (estimate(problem, solution), or on the
/// processes' pieces of the mesh, estimate_error_of_pieces, when e.piece) as the stage
/// "estimate", wherever the displacement is finite.
template <int dim, class Solved, class Estimate>
void estimate_solution(const SceneEngines& e, Solved& s, Estimate&& estimate) {
  if (s.solution.u.size() == 0 || !s.solution.u.allFinite()) return;
  if (e.piece) {  // each process estimates the cells it owns, and every process sums the whole mesh's
    s.estimate = estimate_error_of_pieces<dim>(s.built->problem, s.solution, *e.piece, *process_rows());
  } else {
    s.estimate = estimate(s.built->problem, s.solution);
  }
  s.solution.stages.push_back("estimate");
  s.solution.timings["estimate"] = s.estimate->seconds;
  s.solution.timings["total"] += s.estimate->seconds;
}

/// Whether every file a solve of the scene, of one body or several, writes is made from the
/// processes' pieces of its mesh and the gathered solution (whole_of_pieces): result.json (the
/// whole mesh's size and stress peak, the bodies' cells and loads), contact.csv,
/// displacement.csv (a piece holds every vertex), stress.csv (each process's rows gathered on
/// the first), history.csv, solution.vtu and each body's file (in pieces), scene.toml, the
/// figures (a plane's boundary edges, edges and elements, a solid's boundary faces, gathered),
/// a solid's contact-surface.vtu (its contact faces gathered) and a path's files (its steps'
/// records; its last step's files as a static solve's); not an adaptive solve's files.
bool results_of_pieces(const Scene& scene);

/// After a solve on pieces of the mesh (e.piece), once its memory is given back: the whole
/// mesh's problem in s.built (the results' mesh, as in one process) on a process whose mesh
/// was a piece, with the problem's data at `t` (set_load_factor) for the end of a path; a
/// process that keeps its piece (e.writes_to_folder, not writing; or writing only what the
/// pieces make, results_of_pieces) records its cells' numbers instead (s.piece_cells), and
/// where every process keeps its piece, what the results need of the whole mesh is gathered
/// (s.of_pieces, whole_of_pieces of s.solution, a path's last step's; collective). A path's
/// files written as its steps came (s.path_output) keep the piece they were written from.
template <int dim, class Solved>
void make_results_mesh_whole(const Scene& scene, const SceneEngines& e, Solved& s, std::optional<double> t = {}) {
  if (!e.piece) return;
  // the same on every process, whether or not its piece holds every cell: collective
  if (e.writes_to_folder && results_of_pieces(scene)) {
    s.piece_cells = e.piece->cells;
    const auto& mesh = s.built->mesh;
    const bool displaced = s.solution.u.size() == dim * static_cast<Eigen::Index>(mesh.num_vertices());
    s.of_pieces = std::make_shared<const WholeOfPieces>(
        whole_of_pieces<dim>(s.built->problem, displaced ? s.solution.u : Eigen::VectorXd(), *e.piece, *process_rows(),
                             wanted_files(scene, s.built->has_contact), s.built->bodies));
    return;
  }
  const auto* given = std::any_cast<WholeProblem<dim>>(&e.whole_problem);  // a piece of a mesh given
  if (!given && static_cast<int>(e.piece->cells.size()) == e.piece->whole_cells) return;
  if (e.writes_to_folder && !s.holds_results) {
    s.piece_cells = e.piece->cells;
    return;
  }
  const auto started = std::chrono::steady_clock::now();
  if (s.path_output) s.path_output->piece = std::shared_ptr<const void>(std::move(s.built));
  s.built = given ? (*given)() : build_problem<dim>(scene);
  if (t) set_load_factor(scene, *t, s.built->problem);
  s.mesh_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

/// The engines the scene names (solver.linear, solver.minimizer, solver.search): an unknown or
/// unbuilt name is an InputError naming its key, before any work.
SceneEngines make_scene_engines(const Scene& scene, std::function<void(const GlobalSearchProgress&)> progress,
                                std::function<bool(const IterationRecord&)> callback);

/// Records the engines `e` and the minimizer options in a solve of either dimension
/// (SceneSolve, SceneSolve3D).
template <class Solved>
void record_engines(const SceneEngines& e, Solved& s) {
  s.linear = e.linear;
  s.minimizer = e.minimizer_name;
  s.search = e.search;
  s.holds_results = e.holds_results;
  s.processes = e.processes;
  s.options = e.options;
}

/// The engines the scene names (make_scene_engines), recorded in `s` with the minimizer options
/// (o.callback moved into them), then the problem built (on o.mesh when given) with its time.
/// on_built is left to the caller.
SceneEngines prepare_scene_solve(const Scene& scene, SceneSolveOptions& o, SceneSolve& s);

/// What result.json records of any solved scene (SceneSolve or SceneSolve3D): the scene, the
/// mesh's description, the engines, the search, the options in effect, the mesh time, the
/// unknowns, the processes, the warnings, the error estimate, the cell of the largest von
/// Mises stress (when the run holds the displacement) and the figures' formats.
template <class Solved>
RunInfo run_info_common(const Scene& scene, const Solved& solved) {
  const MinimizerOptions& mo = solved.options;
  RunInfo info;
  info.scene_name = scene.title;
  info.scene_toml = to_toml(scene);
  info.mesh = solved.mesh_description.empty() ? scene_mesh_description(scene) : solved.mesh_description;
  info.linear = solved.linear;
  info.minimizer = solved.minimizer;
  info.search = solved.search;
  info.options = {{"tolerance", mo.tolerance},
                  {"max_iterations", mo.max_iterations},
                  {"stabilization", to_string(scene.material.stabilization)},
                  {"scene", scene.source}};
  info.mesh_seconds = solved.mesh_seconds;
  info.dofs = solved.solution.unknowns;
  info.mesh_pieces = solved.mesh_pieces;
  info.vtu_pieces = solved.share ? solved.processes : 0;
  info.grid_sequence = solved.grid_sequence;
  info.processes = solved.processes;
  info.warnings = solved.warnings;
  info.error_estimate = solved.estimate;
  const auto& mesh = solved.built->mesh;
  constexpr int dim = std::is_same_v<std::decay_t<decltype(mesh)>, Mesh3D> ? 3 : 2;
  if (solved.of_pieces) {  // the results are written from this process's piece of the mesh
    info.of_pieces = solved.of_pieces;
    info.stress = solved.of_pieces->stress;
  } else if (solved.holds_results && solved.solution.u.size() == dim * static_cast<Eigen::Index>(mesh.num_vertices())) {
    info.stress = stress_peak(mesh, cell_stresses(mesh, solved.built->problem.elasticity.materials, solved.solution.u));
  }
  info.figure_formats = scene.figure_formats;
  // the bodies' ranges of the whole mesh, where the processes' pieces gathered them
  info.bodies = solved.of_pieces ? solved.of_pieces->bodies : solved.built->bodies;
  if (solved.holds_results && !info.bodies.empty())
    info.bodies_record = detail::bodies_json(
        solved.of_pieces ? solved.of_pieces->body_loads : detail::body_loads(solved.built->problem, info.bodies),
        solved.solution, info.bodies);
  return info;
}

/// The friction model of a contact part with friction as its scene names it, for result.json's
/// friction.models: {"part", "law"} with "coefficient" for Coulomb's law and "bound_table" for
/// a Tresca bound given as a table (both solved as Tresca laws of bound 1 scaled node by node,
/// FrictionBound), else the law's own name.
template <int dim>
nlohmann::json friction_model_json(const BasicContactPart<dim>& part) {
  nlohmann::json m{{"part", part.name}, {"law", part.friction->name()}};
  if (part.friction_bound && part.friction_bound->kind == FrictionBound::Kind::coulomb) {
    m["law"] = "coulomb";
    m["coefficient"] = part.friction_bound->coefficient;
  } else if (part.friction_bound) {
    m["bound_table"] = part.friction_bound->table;
  }
  return m;
}

/// A friction model of friction_model_json in the summary's words: "coulomb (mu = 0.3)",
/// "tresca (bound table h(u_nu) of 2 points)", "tresca".
inline std::string friction_model_text(const nlohmann::json& m) {
  std::ostringstream o;
  o << m.at("law").get<std::string>();
  if (m.contains("coefficient")) o << " (mu = " << m.at("coefficient").get<double>() << ")";
  if (m.contains("bound_table"))
    o << " (bound table h(u_nu) of " << m.at("bound_table").size() << (m.at("bound_table").size() == 1 ? " point)" : " points)");
  return o.str();
}

/// `items` ", "-joined, each once, in order.
inline std::string joined_once(const std::vector<std::string>& items) {
  std::vector<std::string> once;
  for (const auto& i : items)
    if (std::find(once.begin(), once.end(), i) == once.end()) once.push_back(i);
  std::string r;
  for (const auto& i : once) r += (r.empty() ? "" : ", ") + i;
  return r;
}

/// What result.json and the plots record of a problem's contact parts: the normal laws'
/// breakpoints (sorted, each once), whether a gap bounds u_nu, the first obstacle (plane), the
/// friction models as the scene names them (friction_model_json).
template <int dim>
void add_contact_parts(RunInfo& info, const std::vector<BasicContactPart<dim>>& parts) {
  for (const auto& part : parts) {
    if (part.law && part.constraint != ConstraintKind::bilateral)
      for (double b : part.law->breakpoints())
        if (std::find(info.law_breakpoints.begin(), info.law_breakpoints.end(), b) == info.law_breakpoints.end())
          info.law_breakpoints.push_back(b);
    info.gap_bound = info.gap_bound || part.constraint == ConstraintKind::one_sided || part.constraint == ConstraintKind::box;
    if constexpr (dim == 2)
      if (part.obstacle && !info.obstacle) info.obstacle = part.obstacle;
    if (part.friction) info.friction_models.push_back(friction_model_json(part));
  }
  std::sort(info.law_breakpoints.begin(), info.law_breakpoints.end());
  std::vector<std::string> laws, texts;
  for (const auto& m : info.friction_models) laws.push_back(m.at("law")), texts.push_back(friction_model_text(m));
  info.friction_law = joined_once(laws);
  info.friction_summary = joined_once(texts);
}

/// An InputError a solve of `scene` found without a key, again with the scene's key of what it
/// is about (InputError::about): `contact` for the contact boundary, `clamped` or `dirichlet`
/// (whichever the scene has) for the supports; any other error as it is.
[[noreturn]] inline void rethrow_naming_scene_key(const Scene& scene, const InputError& e) {
  if (!e.where().empty() || e.about() == ProblemPart::unknown) throw;  // the error as it was thrown
  if (e.about() == ProblemPart::contact)
    throw InputError("contact: " + e.detail(), scene.where("contact")).mark_about(e.about());
  throw InputError(e.detail() + " ([clamped] and [[dirichlet]])",
                   scene.where(scene.lines.count("clamped") ? "clamped" : scene.lines.count("dirichlet") ? "dirichlet" : ""))
      .mark_about(e.about());
}

/// solve_scene or solve_scene_3d, chosen by the options' type (code written once for the
/// dimension: an adaptive step, a grid of a grid sequence).
SceneSolve solve_scene_of(const Scene& scene, SceneSolveOptions o);
SceneSolve3D solve_scene_of(const Scene& scene, SceneSolve3DOptions o);

/// The start of a static solve on the scene's own mesh (e.scene_mesh) from its grid sequence
/// (e.grid_levels coarser grids, hemivem/scene/grid_sequence.hpp): the scene solved on the
/// coarsest grid from zero, then on each finer one from the solve before carried onto its grid
/// (values_on_finer_grid), the last carried onto the scene's grid; every coarser grid's solve
/// recorded in s.grid_sequence, coarsest first. Empty without levels, and when the solve starts
/// from a displacement it was given (`given_start`) or is on a mesh it was given: for those an
/// InputError naming solver.grid_sequence when the scene asks for a count of grids. Collective on
/// the full-space route across processes: every process solves each grid.
template <int dim>
Eigen::VectorXd grid_sequence_start(const Scene& scene, const SceneEngines& e, BasicSceneSolve<dim>& s,
                                    bool given_start);

/// The order the processes of the full-space route share a mesh's vertices along: a piece's
/// (e.piece: a generated box's is numbered in slabs already, the piece kept of a mesh made whole
/// follows its mesh's Hilbert order); a mesh held whole on every process (several bodies, an
/// adaptive solve's refined mesh) is shared along hilbert_vertex_order, whatever its own order.
template <int dim>
std::vector<int> shared_vertex_order(const SceneEngines& e, const MeshOf<dim>& mesh) {
  return e.piece ? e.piece->vertices.order : hilbert_vertex_order(mesh);
}

/// Solves s.built->problem with the engines `e` as every static solve of a scene does, in
/// either dimension: BasicContactSolver<dim> with the condition estimate, the reduced problem
/// when `reduced` is not null (the full-space route has none and leaves it) and a warm start
/// from `start` when it is not empty (otherwise from the scene's grid sequence, the stage
/// "grid_sequence", where it runs: grid_sequence_start), a defect found in setting the problem up named by the
/// scene's key (rethrow_naming_scene_key); then the warnings (the scene's, the conditioning's) and, wherever the displacement is (every
/// process of the full-space route across processes; not the ranks > 0 of mumps-mpi), the error
/// estimate estimate(problem, solution) as the stage "estimate".
template <int dim, class Solved, class Estimate>
void solve_built(const Scene& scene, SceneEngines& e, Solved& s, ReducedProblem* reduced, const Eigen::VectorXd& start,
                 Estimate&& estimate) {
  const NonsmoothMinimizer* minimizers[] = {e.minimizer.get()};
  // what holds the engine, reset: its time the stage "release"
  const auto give_back = [&s](auto& holder) {
    const auto released = std::chrono::steady_clock::now();
    holder.reset();
    const double release = std::chrono::duration<double>(std::chrono::steady_clock::now() - released).count();
    s.solution.timings["release"] += release;
    s.solution.timings["total"] += release;
  };
  // with no start given, the scene's coarser grids solved first may give one (grid_sequence_start)
  const auto sequence_started = std::chrono::steady_clock::now();
  Eigen::VectorXd sequenced = grid_sequence_start<dim>(scene, e, s, start.size() > 0);
  const double sequence_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sequence_started).count();
  const Eigen::VectorXd& from = start.size() > 0 ? start : sequenced;
  try {
    if (e.krylov && e.processes > 1) {  // the full-space route across processes, each holding the results
      // no reduced problem: `reduced` is left untouched, as BasicContactSolver::export_reduced does
      // the coarser grids' displacement moved in, given back once each process rotated its rows
      Eigen::VectorXd whole_start = start.size() > 0 ? Eigen::VectorXd(start) : std::move(sequenced);
      s.solution = solve_full_space_shares<dim>(s.built->problem, *e.krylov, krylov_world(), make_distributed_rows,
                                                s.options, std::move(whole_start),
                                                shared_vertex_order<dim>(e, s.built->mesh));
      give_back(e.krylov);  // the engine, as in one process below
    } else {
      std::optional<BasicContactSolver<dim>> solver;
      if (e.krylov)
        solver.emplace(s.built->problem, std::move(e.krylov), s.options);
      else
        solver.emplace(s.built->problem, std::move(e.factorization), s.options);
      solver->estimate_condition(true).export_reduced(reduced);
      if (from.size() > 0) solver->start_from(&from);
      s.solution = std::move(solver->run(minimizers).front());
      // the solver's factorization is given back here, before the outputs: its time is a stage
      give_back(solver);
    }
  } catch (const InputError& error) {
    rethrow_naming_scene_key(scene, error);
  }
  if (!s.grid_sequence.empty()) {  // the coarser grids' solves, a stage of the scene's
    s.solution.timings["grid_sequence"] = sequence_seconds;
    s.solution.timings["total"] += sequence_seconds;
    s.solution.stages.insert(s.solution.stages.begin(), "grid_sequence");
  }
  s.warnings = s.built->warnings;
  if (std::string w = conditioning_warning(s.solution.condition_estimate); !w.empty()) s.warnings.push_back(std::move(w));
  // where the displacement is: on every process of the full-space route across processes, whose
  // adaptive steps refine alike (not on the ranks > 0 of mumps-mpi)
  estimate_solution<dim>(e, s, std::forward<Estimate>(estimate));
  if (e.piece && e.writes_to_folder) s.share = e.piece->vertices;
  make_results_mesh_whole<dim>(scene, e, s);
}

/// The memory a solve of the scene's generated mesh needs fits (require_memory, the
/// estimate of scene/resources.hpp), or an InputError at `where`, before any work.
void require_memory_of(const Scene& scene, const std::string& where);

/// InputError naming solver.linear when the scene's engine runs across processes (mumps-mpi):
/// a loading path runs in one.
void refuse_path_across_processes(const Scene& scene);

/// Solves the scene's loading path on s.built (a problem with contact; InputError naming the
/// scene's [path] otherwise) with the engines `e`, in either dimension: BasicPathSolver<dim>
/// over the scene's load factors and frames, a defect found in setting it up named by the
/// scene's key; s.solution is the last step as a static solve reports it (its problem set to the
/// last t, so that the error estimate and every output read the path's end state) and s.path
/// every step. `on_step` is called after each step.
template <int dim, class Solved>
void solve_path_built(const Scene& scene, SceneEngines& e, Solved& s, std::function<void(const BasicPathStep<dim>&)> on_step,
                      const std::filesystem::path& out = {});

}  // namespace hemivem::app::detail
