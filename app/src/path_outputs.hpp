// The files of a loading path in an output folder (docs/reference/outputs.md): the contact nodes
// of every step, the displacement of every frame, the ParaView collection of the frames and
// the load-displacement figure, written once for plane (dim = 2) and solid (dim = 3) bodies.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/support/output_folder.hpp>

namespace hemivem::app {

/// path-contact.csv: one row per step and contact node.
template <int dim>
void write_path_contact_csv(std::ostream& stream, const BasicPathSolution<dim>& path);
/// path-displacement.csv: one row per frame and vertex.
template <class MeshType, int dim>
void write_path_displacement_csv(std::ostream& stream, const MeshType& mesh, const BasicPathSolution<dim>& path);
/// solution.pvd: the frames' files with their t as ParaView's timesteps.
template <int dim>
void write_pvd(std::ostream& stream, const BasicPathSolution<dim>& path);
/// "solution-0007.vtu" for step 7 (four digits at least).
std::string frame_file(int step);
/// The frame files of a path, in order.
template <int dim>
std::vector<std::string> frame_files(const BasicPathSolution<dim>& path);
/// The names solution-<digits>.vtu already in `dir` (an earlier path's frames).
std::vector<std::string> frame_files_in(const std::filesystem::path& dir);
/// The names of the files in `dir` that the regular expression `pattern` matches whole (none
/// when `dir` is not a folder).
std::vector<std::string> files_matching(const std::filesystem::path& dir, const std::string& pattern);
/// result.json's "path": steps, converged steps, jumps, the last t and the file with the rest.
template <int dim>
nlohmann::json path_summary_json(const BasicPathSolution<dim>& path);
/// path.png: the normal (and friction) resultant of the contact forces against the mean normal
/// displacement of the contact nodes, and the contact and stick zones against t; jumps marked.
template <int dim>
Figure path_figure(const BasicPathSolution<dim>& path, const RunInfo& info);

/// The files of the run's path (RunInfo::path) that `want` names: path.json, path-contact.csv,
/// path-displacement.csv and, for solution.pvd, a VTU per frame (`write_frame` writes one
/// frame's solution) with the collection; each file written is added to `report`. Without a
/// path, the names wanted are reported as skipped.
template <class MeshType, int dim>
void write_path_files(OutputTransaction& tx, const std::filesystem::path& dir, const MeshType& mesh,
                      const BasicPathSolution<dim>* path, const std::function<bool(const std::string&)>& want,
                      const std::function<void(std::ostream&, const BasicContactSolution<dim>&)>& write_frame,
                      OutputReport& report);

/// The names a run with this path may own in its folder: the path's frames, when solution.pvd
/// is wanted (for result.json's list of files).
template <int dim>
std::vector<std::string> listed_frames(const BasicPathSolution<dim>* path,
                                       const std::function<bool(const std::string&)>& want);

}  // namespace hemivem::app
