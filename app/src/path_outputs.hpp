// The files of a loading path in an output folder (docs/reference/outputs.md): the contact nodes
// of every step, the displacement of every frame, the ParaView collection of the frames and
// the load-displacement figure.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/path/path.hpp>

namespace hemivem::app {

/// path-contact.csv: one row per step and contact node.
void write_path_contact_csv(std::ostream& stream, const PathSolution& path);
/// path-displacement.csv: one row per frame and vertex.
void write_path_displacement_csv(std::ostream& stream, const Mesh& mesh, const PathSolution& path);
/// solution.pvd: the frames' files with their t as ParaView's timesteps.
void write_pvd(std::ostream& stream, const PathSolution& path);
/// "solution-0007.vtu" for step 7 (four digits at least).
std::string frame_file(const PathStep& step);
/// The frame files of a path, in order.
std::vector<std::string> frame_files(const PathSolution& path);
/// The names solution-<digits>.vtu already in `dir` (an earlier path's frames).
std::vector<std::string> frame_files_in(const std::filesystem::path& dir);
/// result.json's "path": steps, converged steps, jumps, the last t and the file with the rest.
nlohmann::json path_summary_json(const PathSolution& path);
/// path.png: the normal (and friction) resultant of the contact forces against the mean normal
/// displacement of the contact nodes, and the contact and stick zones against t; jumps marked.
Figure path_figure(const PathSolution& path, const RunInfo& info);

}  // namespace hemivem::app
