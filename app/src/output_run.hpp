// The writing of one run's output folder, shared by the writers of plane and solid solves
// (private to hemivem::app): the names the run owns, the transaction, the files wanted,
// result.json's list of files, the figures, and the files every solve writes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/vtu.hpp>
#include <hemivem/app/text_writer.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/support/output_folder.hpp>

namespace hemivem::app::detail {

/// history.csv: the minimizer's iterations.
template <int dim>
void write_history_csv(std::ostream& stream, const BasicContactSolution<dim>& s) {
  TextWriter os(stream);
  os << "iteration,reduced_objective,primal,dual,active,seconds\n";
  if (!s.minimizer) return;
  for (const auto& r : s.minimizer->history)
    os << r.iteration << ',' << r.objective << ',' << r.primal << ',' << r.dual << ',' << r.active << ',' << r.seconds
       << '\n';
}

/// contact.csv: one row per contact node: vertex, position, u_nu, forces, pressure, state,
/// gap, normal; with friction u_tau, the friction force and traction (a plane's along tau; a
/// solid's as vectors u_tau_x.., friction_force_x.. and the traction's length) and the friction
/// state; with several parts the node's part.
template <int dim>
void write_contact_csv(std::ostream& stream, const BasicContactSolution<dim>& s) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  TextWriter os(stream);
  const bool tangential = std::any_of(s.contact.begin(), s.contact.end(),
                                      [](const auto& n) { return n.friction_state != FrictionState::none; });
  const bool parts = s.contact_parts.size() > 1;  // several contact parts: each node's
  // two bodies: the other body's vertex across the contact
  const bool pairs = std::any_of(s.contact.begin(), s.contact.end(), [](const auto& n) { return n.partner >= 0; });
  os << "vertex";
  for (int c = 0; c < dim; ++c) os << ',' << axes[c];
  os << ",u_nu,law_force,reaction,pressure,state,gap";
  for (int c = 0; c < dim; ++c) os << ",n" << axes[c];
  if (tangential && dim == 2) os << ",u_tau,friction_force,friction_traction,friction_state";
  if (tangential && dim == 3)
    os << ",u_tau_x,u_tau_y,u_tau_z,friction_force_x,friction_force_y,friction_force_z,friction_traction,friction_state";
  os << (parts ? ",part" : "") << (pairs ? ",partner" : "") << "\n";
  for (const auto& n : s.contact) {
    os << n.vertex;
    for (int c = 0; c < dim; ++c) os << ',' << n.x(c);
    os << ',' << n.u_nu << ',' << n.law_force << ',' << n.reaction << ',' << n.pressure() << ',' << to_string(n.state) << ',';
    if (!std::isnan(n.gap)) os << n.gap;  // empty: no gap used (bilateral)
    for (int c = 0; c < dim; ++c) os << ',' << n.normal(c);
    if (tangential && n.friction_state != FrictionState::none) {
      if constexpr (dim == 2) {
        os << ',' << n.u_tau << ',' << n.friction_force;
      } else {
        for (int c = 0; c < 3; ++c) os << ',' << n.u_tangential(c);
        for (int c = 0; c < 3; ++c) os << ',' << n.friction_vector(c);
      }
      os << ',' << n.friction_force / n.weight << ',' << to_string(n.friction_state);
    } else if (tangential) {
      os << (dim == 2 ? ",,,," : ",,,,,,,,");  // a frictionless part beside one with friction
    }
    if (parts) os << ',' << contact_part_name(s, n);
    if (pairs) {
      os << ',';
      if (n.partner >= 0) os << n.partner;  // empty: a foundation's or an obstacle's node
    }
    os << '\n';
  }
}

/// displacement.csv: one row per vertex: vertex, position, displacement; with several bodies,
/// the vertex's body.
template <class MeshType>
void write_displacement_csv(std::ostream& stream, const MeshType& mesh, const Eigen::VectorXd& u,
                            const std::vector<BodyRange>& bodies = {}) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  constexpr int dim = std::is_same_v<MeshType, Mesh3D> ? 3 : 2;
  TextWriter os(stream);
  os << "vertex";
  for (int c = 0; c < dim; ++c) os << ',' << axes[c];
  for (int c = 0; c < dim; ++c) os << ",u" << axes[c];
  os << (bodies.empty() ? "" : ",body") << '\n';
  std::size_t b = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    os << v;
    for (int c = 0; c < dim; ++c) os << ',' << mesh.vertex(v)(c);
    for (int c = 0; c < dim; ++c) os << ',' << u(dim * v + c);
    if (!bodies.empty()) {
      while (b + 1 < bodies.size() && !bodies[b].has_vertex(v)) ++b;
      os << ',' << bodies[b].name;
    }
    os << '\n';
  }
}

/// stress.csv: one row per cell: cell, its centroid, the components of its projected stress
/// (a plane's sxx, syy, szz, sxy; a solid's sxx, syy, szz, syz, sxz, sxy) and von_mises; the
/// whole mesh's rows gathered from the pieces (WholeOfPieces::stress_rows) when `pieces` is
/// given, `mesh` being a piece.
template <class MeshType>
void write_stress_csv(std::ostream& stream, const MeshType& mesh, const MaterialTable& materials, const Eigen::VectorXd& u,
                      const WholeOfPieces* pieces = nullptr) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  constexpr int dim = std::is_same_v<MeshType, Mesh3D> ? 3 : 2;
  TextWriter os(stream);
  os << "cell";
  for (int c = 0; c < dim; ++c) os << ',' << axes[c];
  os << (dim == 2 ? ",sxx,syy,szz,sxy" : ",sxx,syy,szz,syz,sxz,sxy") << ",von_mises\n";
  const auto row = [&os](std::size_t e, const double* x, const BasicCellStress<dim>& s) {
    os << static_cast<long long>(e);
    for (int c = 0; c < dim; ++c) os << ',' << x[c];
    os << ',' << s.xx << ',' << s.yy << ',' << s.zz;
    if constexpr (dim == 3) os << ',' << s.yz << ',' << s.xz;
    os << ',' << s.xy << ',' << s.von_mises() << '\n';
  };
  if (pieces) {
    constexpr std::size_t width = dim + 6;
    const std::vector<double>& rows = pieces->stress_rows;
    for (std::size_t e = 0; e < rows.size() / width; ++e) {
      const double* r = rows.data() + e * width;
      BasicCellStress<dim> s;
      s.xx = r[dim], s.yy = r[dim + 1], s.zz = r[dim + 2], s.yz = r[dim + 3], s.xz = r[dim + 4], s.xy = r[dim + 5];
      row(e, r, s);
    }
    return;
  }
  const auto stresses = cell_stresses(mesh, materials, u);
  for (std::size_t e = 0; e < stresses.size(); ++e) {
    const auto x = mesh.centroid(static_cast<int>(e));
    row(e, x.data(), stresses[e]);
  }
}

class OutputRun;

/// The files every solve writes, in either dimension, when wanted: result.json (`result` of the
/// run's listed record), contact.csv, displacement.csv, stress.csv, history.csv and solution.vtu
/// (with the error indicators), with several bodies each body's VTU and solution.vtm. A solve
/// written in pieces (info.vtu_pieces, write_outputs_in_pieces) has each process's piece in
/// the staging folder already: solution.pvtu then names them, declared by `pieces`.
template <class MeshType, int dim, class Result>
void write_solve_files(OutputRun& run, const MeshType& mesh, const MaterialTable& materials,
                       const BasicContactSolution<dim>& solution, const RunInfo& info, const Result& result,
                       const SolutionVtu* pieces = nullptr);

/// Whether the first process writes `file` of a solve in `dim` dimensions, of one body or
/// several, from its piece of the mesh and what is gathered from the others' (WholeOfPieces):
/// result.json, the CSV files, solution.vtu (and each body's file) in pieces, scene.toml,
/// deformed.png, a plane's u_nu.png and error.png, a solid's contact-surface.vtu and
/// pressure.png, and a path's files (path.json, path-contact.csv, path-displacement.csv,
/// solution.pvd, path.png); not an adaptive solve's (mesh.poly2d, mesh.png, adapt.png,
/// adapt.pvd).
bool made_from_pieces(const std::string& file, int dim);

/// Whether a run on pieces makes `file` from what the processes gather of their pieces for it
/// alone (stress.csv, the figures, a solid's contact-surface.vtu), which they gather only for
/// the files they are told (WholeOfPieces::serves).
bool gathered_for_itself(const std::string& file);

/// The piece of process `rank` of solution.pvtu: "solution.piece-3.vtu".
std::string vtu_piece_file(int rank);

/// write_outputs (either dimension; `contact_faces` a solid's, null for a plane), collective
/// over the processes of a solve across processes whose mesh was made in pieces (the share
/// of this process's vertices, BasicSceneSolve::share): the first process opens
/// the folder's transaction and every process writes its piece of solution.pvtu into it
/// (SolutionVtu::write_share); the first then writes the other files and solution.pvtu, and
/// commits. Every process calls it with the same `wanted`; it returns the first process's
/// report, and an empty one on the others. A piece that cannot be written is an InputError on
/// its process and on the first, and the folder keeps its previous outputs. `mesh` is the whole
/// mesh, or on a process that does not write the piece it kept, whose cells are the whole
/// mesh's `piece_cells` (BasicSceneSolve::piece_cells).
template <class MeshType, int dim>
OutputReport write_outputs_in_pieces(const std::filesystem::path& dir, const MeshType& mesh, const MaterialTable& materials,
                                     const std::vector<int>* contact_faces, const BasicContactSolution<dim>& solution,
                                     const RunInfo& info, const std::vector<std::string>& wanted,
                                     const VertexShare& share, const std::vector<int>& piece_cells);

/// The file of body `body` of a scene of several in its output folder: "solution.body-upper.vtu".
/// A name that cannot name a file so (other than 1 to 64 ASCII letters, digits, '-' or '_', as
/// a scene's [[body]] names are) is an InputError naming it. The dot keeps these names apart
/// from a path's frames (solution-0007.vtu) whatever a body is named.
std::string body_vtu_file(const std::string& body);

/// The files of the bodies `bodies`, in their order (body_vtu_file); InputError for a name that
/// cannot name a file and for two bodies whose files would be one (names equal but for case).
std::vector<std::string> body_vtu_files(const std::vector<BodyRange>& bodies);

/// The piece of process `rank` of body `body`'s file written in pieces:
/// "solution.body-upper.piece-3.vtu".
std::string body_piece_file(const std::string& body, int rank);

/// A scene of several bodies (info.bodies) whose solution.vtu is wanted: a
/// solution.body-NAME.vtu per body (`vtu` restricted to it), then solution.vtm, the multiblock
/// dataset naming them by body; nothing for one body. A solve written in pieces
/// (info.vtu_pieces; `vtu` null) has each process's piece of each body (body_piece_file) in the
/// staging folder already: solution.vtm then names them, each body a block of its pieces.
void write_body_vtus(OutputRun& run, const RunInfo& info, const SolutionVtu* vtu);

/// The file of step `step` of an adaptive solve in its output folder: "adapt-step-3.vtu".
std::string adapt_step_file(std::size_t step);

/// adapt.pvd, when wanted: an adapt-step-K.vtu per step of info.adapt_steps (K = 0, 1, ...),
/// then the collection naming them with K as their time; without the steps (not an adaptive
/// solve, or the output vtu not kept) the reason in the run's report.
void write_adapt_steps(OutputRun& run, const RunInfo& info);

/// InputError for a name of `wanted` that is not in `known` (`what`: "", or " of a
/// three-dimensional solve"), listing the known names.
void require_known_outputs(const std::vector<std::string>& wanted, const std::vector<std::string>& known,
                           const std::string& what);

/// One run's folder: the files are written into a transaction that owns `known`, `others` (the
/// other dimension's names), the figures' names in every format, an earlier path's frames and
/// `frames` (this run's), an earlier adaptive solve's steps and this run's (adapt_step_file),
/// solution.vtm and an earlier run's solution.body-NAME.vtu, and that commit() makes the folder
/// at once. result.json lists the files wanted, in the order of `known` (a figure in each of
/// info.figure_formats, an adaptive solve's steps before adapt.pvd, the bodies' files and
/// solution.vtm after solution.vtu), then the frames when solution.pvd is wanted.
class OutputRun {
 public:
  OutputRun(const std::filesystem::path& dir, const std::vector<std::string>& known, const std::vector<std::string>& others,
            const std::vector<std::string>& wanted, const RunInfo& info, const std::vector<std::string>& frames);
  /// The folder's transaction opened before the run is known (a path writing its steps as
  /// they come), owning `frames` (the frames it may write) and `adapt_steps` steps of an
  /// adaptive solve; list() then records the run.
  OutputRun(const std::filesystem::path& dir, const std::vector<std::string>& known, const std::vector<std::string>& others,
            const std::vector<std::string>& wanted, std::size_t adapt_steps, const std::vector<std::string>& frames);
  /// Records the run `info` with the files result.json lists: the wanted ones, and `frames`.
  void list(const RunInfo& info, const std::vector<std::string>& frames);

  bool want(const std::string& name) const;
  /// The output folder as given.
  const std::filesystem::path& dir() const noexcept { return dir_; }
  /// Writes `name` when it is wanted.
  void write(const std::string& name, const std::function<void(std::ostream&)>& body);
  /// The run's record with the files it lists (RunInfo::files).
  const RunInfo& listed() const noexcept { return listed_; }
  OutputTransaction& transaction() noexcept { return tx_; }
  OutputReport& report() noexcept { return report_; }
  /// The figures `make` adds, drawn into the staging folder: one that cannot be made is skipped
  /// with its reason (make may also skip one in the report); a file that cannot be written is a
  /// WriteError.
  void draw(const std::function<void(std::vector<Figure>&)>& make);
  /// result.json again when a file could not be made (it lists what was written, and the
  /// figures that failed among its warnings), then the commit: the folder holds exactly this
  /// run's outputs.
  OutputReport finish(const std::function<nlohmann::json(const RunInfo&)>& result_json);

 private:
  std::filesystem::path dir_;
  std::vector<std::string> known_;
  std::vector<std::string> wanted_;
  OutputTransaction tx_;
  OutputReport report_;
  RunInfo listed_;
  std::vector<std::pair<std::string, std::string>> failed_;  ///< figures not drawn: name, why
};

template <class MeshType, int dim, class Result>
void write_solve_files(OutputRun& run, const MeshType& mesh, const MaterialTable& materials,
                       const BasicContactSolution<dim>& solution, const RunInfo& info, const Result& result,
                       const SolutionVtu* pieces) {
  run.write("result.json", [&](std::ostream& os) { os << result(run.listed()).dump(2) << '\n'; });
  run.write("contact.csv", [&](std::ostream& os) { write_contact_csv(os, solution); });
  run.write("displacement.csv", [&](std::ostream& os) { write_displacement_csv(os, mesh, solution.u, info.bodies); });
  run.write("stress.csv", [&](std::ostream& os) { write_stress_csv(os, mesh, materials, solution.u, info.of_pieces.get()); });
  run.write("history.csv", [&](std::ostream& os) { write_history_csv(os, solution); });
  if (run.want("solution.vtu") && info.vtu_pieces > 0) {  // the processes' pieces, then the file naming them
    if (!pieces) throw InternalError("solution.pvtu without its pieces");
    std::vector<std::string> files;
    for (int k = 0; k < info.vtu_pieces; ++k) {
      files.push_back(vtu_piece_file(k));
      run.report().written.push_back(run.dir() / files.back());
    }
    run.transaction().write("solution.pvtu", [&](std::ostream& os) { pieces->write_pieces(os, files); });
    run.report().written.push_back(run.dir() / "solution.pvtu");
    write_body_vtus(run, info, nullptr);
  } else if (run.want("solution.vtu")) {  // the arrays made once for the whole and for each body
    const SolutionVtu vtu(mesh, materials, solution, info.error_estimate ? &info.error_estimate->indicators : nullptr);
    run.write("solution.vtu", [&](std::ostream& os) { vtu.write(os); });
    write_body_vtus(run, info, &vtu);
  }
}

}  // namespace hemivem::app::detail

#include "path_outputs.hpp"

namespace hemivem::app::detail {

/// The output folder of a loading path opened before the path runs (SceneSolveOptions::out):
/// its transaction (locked, nothing in the folder changes before the commit), and the path's
/// files, to which each step is added as it is solved; write_results to the same folder then
/// writes the rest and commits (write_path_outputs).
template <int dim>
class FramePieces;

template <int dim>
struct PathOutput {
  using MeshType = std::conditional_t<dim == 2, Mesh, Mesh3D>;
  /// `frames`: the frames the path may write (owned by the transaction); `parts`: the names of
  /// the contact parts; `bodies`: a scene of several bodies' (PathFiles).
  PathOutput(const std::filesystem::path& dir, const std::vector<std::string>& wanted, const std::vector<std::string>& frames,
             const MeshType& mesh, const MaterialTable& materials, std::vector<std::string> parts,
             std::vector<BodyRange> bodies = {});
  OutputRun run;
  PathFiles<dim> files;
  bool written = false;  ///< write_path_outputs has committed it
  /// The problem on a process's piece of the mesh that `files` was given the mesh of, kept
  /// once the solve made the whole mesh for its results (docs/cluster.md).
  std::shared_ptr<const void> piece;
  /// Set when the path's frames are written in pieces (FramePieces): `files` then writes each
  /// frame through it.
  FramePieces<dim>* frame_pieces = nullptr;
};

/// The VTU frames of a loading path across processes whose mesh was made in pieces, written in
/// pieces (docs/reference/outputs.md): at each frame every process writes its piece
/// (solution-0007.piece-K.vtu, SolutionVtu::write_share of its share of the vertices) into the
/// staging folder of the first process's transaction, and the first writes solution-0007.pvtu
/// naming them. A piece that cannot be written is remembered, the process writes no more, and
/// require_written tells every process before the folder is committed.
template <int dim>
class FramePieces {
 public:
  using MeshType = std::conditional_t<dim == 2, Mesh, Mesh3D>;
  /// Collective. The first process passes its path's transaction `tx` (null when it could not
  /// open the folder), the others null; every process learns the staging folder (opened()).
  /// `mesh` (the process's piece, every vertex of the whole mesh) and `materials` are kept by
  /// reference while the path runs; `share`: the process's vertices.
  FramePieces(const OutputTransaction* tx, const MeshType& mesh, const MaterialTable& materials, VertexShare share);
  ~FramePieces();
  /// Whether the first process opened the folder.
  bool opened() const { return !staging_.empty(); }
  /// Writes this process's piece of step `step`'s frame and, on the first process, into `tx`,
  /// the file naming the pieces; returns the frame's files (frame_files_of).
  std::vector<std::string> write(int step, const BasicContactSolution<dim>& frame, OutputTransaction* tx);
  /// Collective: an InputError, on the process that could not write a piece and on the first,
  /// unless every process wrote every piece; `dir` is the output folder, for the message.
  void require_written(const std::filesystem::path& dir);
  /// The processes (a row each), the first process's staging folder, and this process's share
  /// of the vertices: where the last step's solution.vtu goes in pieces (write_path_outputs).
  const RowDistribution& rows() const { return *rows_; }
  const std::filesystem::path& staging() const { return staging_; }
  const VertexShare& share() const { return share_; }

 private:
  std::unique_ptr<RowDistribution> rows_;
  std::filesystem::path staging_;
  const MeshType& mesh_;
  const MaterialTable& materials_;
  VertexShare share_;
  std::string failed_file_, failed_why_;  ///< the piece this process could not write, and why
};

/// InputError unless `dir` is the folder `out` writes and `files` is null (its steps were
/// written there as they came), or when the outputs were written already.
template <int dim>
void require_path_output_folder(const PathOutput<dim>& out, const std::filesystem::path& dir,
                                const std::vector<std::string>* files);

/// The outputs of a path solved with its folder open (`out`, on the process that writes; null
/// on the others): as write_outputs, into out's folder, once (require_path_output_folder of
/// `dir` and `files`). With its frames written in pieces (`pieces`, on every process) and
/// info.vtu_pieces > 0, collective: every process writes its piece of the last step's
/// solution.vtu into the path's transaction first (as write_outputs_in_pieces, `mesh` this
/// process's piece whose cells are the whole mesh's `piece_cells`, or the whole mesh), and
/// every process calls it. `contact_faces`: a solid's, or null.
template <int dim>
OutputReport write_path_outputs(const std::filesystem::path& dir, const std::vector<std::string>* files,
                                PathOutput<dim>* out, FramePieces<dim>* pieces,
                                const typename PathOutput<dim>::MeshType& mesh, const MaterialTable& materials,
                                const std::vector<int>* contact_faces, const BasicContactSolution<dim>& solution,
                                const RunInfo& info, const std::vector<int>& piece_cells);

}  // namespace hemivem::app::detail
