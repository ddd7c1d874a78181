// The files of a loading path in an output folder (docs/reference/outputs.md): path.json, the
// contact nodes of every step, the displacement of every frame, the ParaView collection of the
// frames and the load-displacement figure, written once for plane (dim = 2) and solid (dim = 3)
// bodies, one step at a time: while the path runs (a run given its output folder) or from the
// steps it kept.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/mesh/body_range.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/support/atomic_file.hpp>
#include <hemivem/support/output_folder.hpp>

namespace hemivem::app {

/// "solution-0007.vtu" for step 7 (four digits at least).
std::string frame_file(int step);
/// A frame written in pieces across processes: "solution-0007.pvtu", naming the pieces
/// "solution-0007.piece-K.vtu" (K = 0, 1, ...).
std::string frame_pvtu_file(int step);
std::string frame_piece_file(int step, int piece);
/// The files of step `step`'s frame: frame_file, or, written in `pieces` pieces (> 0), each
/// piece and then the file naming them.
std::vector<std::string> frame_files_of(int step, int pieces);
/// The frame files of the steps a path kept, in order.
template <int dim>
std::vector<std::string> frame_files(const BasicPathSolution<dim>& path);
/// The frames of an earlier path already in `dir`: solution-<digits>.vtu, and of frames written
/// in pieces solution-<digits>.pvtu and solution-<digits>.piece-<digits>.vtu.
std::vector<std::string> frame_files_in(const std::filesystem::path& dir);
/// The names of the files in `dir` that the regular expression `pattern` matches whole (none
/// when `dir` is not a folder).
std::vector<std::string> files_matching(const std::filesystem::path& dir, const std::string& pattern);
/// result.json's "path": steps, converged steps, jumps, the last t and the file with the rest.
template <int dim>
nlohmann::json path_summary_json(const BasicPathSolution<dim>& path);

/// The files of a path that `want` names, written into the staging folder of `tx` as the steps
/// come (add), each step once and never kept: path.json (its steps, then the members that
/// sum the path up), path-contact.csv (a row per step and contact node), path-displacement.csv
/// (a row per frame and vertex) and, for solution.pvd, the files of each frame (`write_frame`);
/// finish() completes them. What is kept per step is one row of path.png's data (7 numbers).
template <int dim>
class PathFiles {
 public:
  using MeshType = std::conditional_t<dim == 2, Mesh, Mesh3D>;
  /// Writes the frame of step `step` into the transaction and returns the files written, the
  /// last the one solution.pvd names.
  using WriteFrame = std::function<std::vector<std::string>(int step, const BasicContactSolution<dim>&)>;
  /// `parts`: the names of the contact parts, by BasicContactNode::part; `bodies`: a scene of
  /// several bodies' (path-displacement.csv's column `body`), empty for one body.
  PathFiles(OutputTransaction& tx, std::function<bool(const std::string&)> want, const MeshType& mesh,
            std::vector<std::string> parts, WriteFrame write_frame, std::vector<BodyRange> bodies = {});
  ~PathFiles();

  /// Writes step `s`: its record, its contact rows, its frame when it has a displacement.
  void add(const BasicPathStep<dim>& s);
  /// path.json's members after the steps and solution.pvd; each file written is added to `report`.
  void finish(const BasicPathSolution<dim>& path, OutputReport& report);
  /// The files of the frames written, in order.
  std::vector<std::string> frames() const;
  /// path.png: the normal (and friction) resultant of the contact forces against the mean
  /// normal displacement of the contact nodes, and the contact and stick zones against t;
  /// jumps marked.
  Figure figure(const RunInfo& info) const;

 private:
  void stage(const std::function<void()>& writes);
  OutputTransaction& tx_;
  std::function<bool(const std::string&)> want_;
  const MeshType& mesh_;
  std::vector<std::string> parts_;
  WriteFrame write_frame_;
  std::vector<BodyRange> bodies_;
  std::unique_ptr<FileInPieces> json_, contact_, displacement_;
  bool tangential_ = false;
  int steps_ = 0;
  std::vector<std::pair<double, std::string>> frames_;  ///< t and file of each frame
  std::vector<std::string> frame_files_;                ///< every file of the frames
  /// per step: t, mean u_nu, normal resultant, friction resultant, zone length, stick length, jump
  std::vector<std::array<double, 7>> rows_;
};

/// The files of the run's path (RunInfo::path) that `want` names, from the steps it kept, with
/// PathFiles (`bodies`: a scene of several bodies'); without a path, the names wanted are
/// reported as skipped. Returns the files' writer (its figure is path.png), or null without a path.
template <class MeshType, int dim>
std::unique_ptr<PathFiles<dim>> write_path_files(OutputTransaction& tx, const MeshType& mesh, const BasicPathSolution<dim>* path,
                                                 const std::function<bool(const std::string&)>& want,
                                                 const typename PathFiles<dim>::WriteFrame& write_frame, OutputReport& report,
                                                 const std::vector<BodyRange>& bodies = {});

/// The frame of a step: its displacement and contact nodes, the contact parts named `parts`.
template <int dim>
BasicContactSolution<dim> frame_of(const BasicPathStep<dim>& step, const std::vector<std::string>& parts);

/// The names a run with this path may own in its folder: the path's frames, when solution.pvd
/// is wanted (for result.json's list of files).
template <int dim>
std::vector<std::string> listed_frames(const BasicPathSolution<dim>* path,
                                       const std::function<bool(const std::string&)>& want);

}  // namespace hemivem::app
