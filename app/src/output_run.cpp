// The writing of one run's output folder (output_run.hpp).
#include "output_run.hpp"

#include <hemivem/error.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/support/atomic_file.hpp>

#include "path_outputs.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <ostream>

namespace hemivem::app::detail {

namespace fs = std::filesystem;

namespace {

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The steps of an earlier adaptive solve in `dir`: adapt-step-<digits>.vtu.
std::vector<std::string> adapt_steps_in(const fs::path& dir) { return files_matching(dir, R"(adapt-step-[0-9]+\.vtu)"); }

// The pieces of an earlier run's solution.pvtu in `dir`: solution.piece-<digits>.vtu.
std::vector<std::string> vtu_pieces_in(const fs::path& dir) { return files_matching(dir, R"(solution\.piece-[0-9]+\.vtu)"); }

// The files of an earlier run's bodies in `dir`: solution.body-<name>.vtu, or in pieces
// solution.body-<name>.piece-<digits>.vtu.
std::vector<std::string> body_vtus_in(const fs::path& dir) {
  return files_matching(dir, R"(solution\.body-[A-Za-z0-9_-]+(\.piece-[0-9]+)?\.vtu)");
}

// The names a run may own: its own, the other dimension's, its figures' in every format, an
// earlier path's frames, its frames, an earlier adaptive solve's steps and its own, solution.vtm
// and an earlier run's bodies' files (a run's own are written whatever the folder holds).
std::vector<std::string> owned_names(const fs::path& dir, const std::vector<std::string>& known,
                                     const std::vector<std::string>& others, const std::vector<std::string>& frames,
                                     std::size_t adapt_steps) {
  std::vector<std::string> owned = known;
  for (const auto& name : others)
    if (!contains(owned, name)) owned.push_back(name);
  for (std::size_t i = 0, n = owned.size(); i < n; ++i)  // a figure's files in the other formats
    if (fs::path(owned[i]).extension() == ".png")
      for (const auto& format : figure_formats())
        if (const std::string file = fs::path(owned[i]).replace_extension(format).string(); !contains(owned, file))
          owned.push_back(file);
  for (const auto& name : frame_files_in(dir)) owned.push_back(name);
  owned.insert(owned.end(), frames.begin(), frames.end());
  for (const auto& name : adapt_steps_in(dir))
    if (!contains(owned, name)) owned.push_back(name);
  for (std::size_t k = 0; k < adapt_steps; ++k)
    if (!contains(owned, adapt_step_file(k))) owned.push_back(adapt_step_file(k));
  for (const char* name : {"solution.vtm", "solution.pvtu"})
    if (!contains(owned, name)) owned.push_back(name);
  for (const auto& name : vtu_pieces_in(dir))
    if (!contains(owned, name)) owned.push_back(name);
  for (const auto& name : body_vtus_in(dir))
    if (!contains(owned, name)) owned.push_back(name);
  return owned;
}

}  // namespace

void require_known_outputs(const std::vector<std::string>& wanted, const std::vector<std::string>& known,
                           const std::string& what) {
  for (const auto& w : wanted)
    if (!contains(known, w)) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError("unknown output '" + w + "'" + what + " (known: " + list + ")");
    }
}

OutputRun::OutputRun(const fs::path& dir, const std::vector<std::string>& known, const std::vector<std::string>& others,
                     const std::vector<std::string>& wanted, const RunInfo& info, const std::vector<std::string>& frames)
    : OutputRun(dir, known, others, wanted, info.adapt_steps ? info.adapt_steps->size() : 0, frames) {
  list(info, frames);
}

OutputRun::OutputRun(const fs::path& dir, const std::vector<std::string>& known, const std::vector<std::string>& others,
                     const std::vector<std::string>& wanted, std::size_t adapt_steps, const std::vector<std::string>& frames)
    : dir_(dir), known_(known), wanted_(wanted), tx_(dir, owned_names(dir, known, others, frames, adapt_steps)) {}

void OutputRun::list(const RunInfo& info, const std::vector<std::string>& frames) {
  listed_ = info;
  listed_.files.clear();
  for (const auto& k : known_) {
    if (!want(k)) continue;
    if (k == "adapt.pvd" && info.adapt_steps)
      for (std::size_t step = 0; step < info.adapt_steps->size(); ++step) listed_.files.push_back(adapt_step_file(step));
    if (k == "solution.vtu" && info.vtu_pieces > 0) {  // written in pieces: each process's, then the file naming them
      for (int p = 0; p < info.vtu_pieces; ++p) listed_.files.push_back(vtu_piece_file(p));
      listed_.files.push_back("solution.pvtu");
    } else if (fs::path(k).extension() != ".png") {
      listed_.files.push_back(k);
    } else {
      for (const auto& format : info.figure_formats) listed_.files.push_back(fs::path(k).replace_extension(format).string());
    }
    if (k == "solution.vtu" && !info.bodies.empty()) {  // each body's, then the multiblock naming them
      for (const BodyRange& b : info.bodies) {
        for (int p = 0; p < info.vtu_pieces; ++p) listed_.files.push_back(body_piece_file(b.name, p));
        if (info.vtu_pieces == 0) listed_.files.push_back(body_vtu_file(b.name));
      }
      listed_.files.push_back("solution.vtm");
    }
  }
  if (want("solution.pvd")) listed_.files.insert(listed_.files.end(), frames.begin(), frames.end());
}

bool OutputRun::want(const std::string& name) const { return contains(wanted_, name); }

std::string vtu_piece_file(int rank) { return "solution.piece-" + std::to_string(rank) + ".vtu"; }

std::string adapt_step_file(std::size_t step) { return "adapt-step-" + std::to_string(step) + ".vtu"; }

std::string body_vtu_file(const std::string& body) {
  if (!valid_body_name(body))
    throw InputError("body '" + body + "': its name names its file solution.body-NAME.vtu, so it is 1 to 64 letters, "
                     "digits, '-' or '_' (ASCII)");
  return "solution.body-" + body + ".vtu";
}

std::vector<std::string> body_vtu_files(const std::vector<BodyRange>& bodies) {
  std::vector<std::string> files;
  std::map<std::string, std::string> folded;  // by the file's name in lower case: the body
  for (const BodyRange& b : bodies) {
    files.push_back(body_vtu_file(b.name));
    std::string key = files.back();
    std::transform(key.begin(), key.end(), key.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    if (const auto [at, fresh] = folded.emplace(key, b.name); !fresh)
      throw InputError("bodies '" + at->second + "' and '" + b.name + "' would write one file " + files.back() +
                       " (their names differ in case at most)");
  }
  return files;
}

std::string body_piece_file(const std::string& body, int rank) {
  const std::string file = body_vtu_file(body);
  return file.substr(0, file.size() - std::string(".vtu").size()) + ".piece-" + std::to_string(rank) + ".vtu";
}

void write_body_vtus(OutputRun& run, const RunInfo& info, const SolutionVtu* vtu) {
  if (info.bodies.empty() || !run.want("solution.vtu")) return;
  if (!vtu && info.vtu_pieces == 0) throw InternalError("the bodies' files without their arrays");
  const std::vector<std::string> files = body_vtu_files(info.bodies);
  // each body's file, or in pieces each process's piece of it (in the staging folder already)
  std::vector<std::vector<std::string>> blocks(files.size());
  for (std::size_t b = 0; b < files.size(); ++b) {
    if (info.vtu_pieces == 0) {
      run.transaction().write(files[b], [&](std::ostream& os) { vtu->write(os, info.bodies[b]); });
      blocks[b] = {files[b]};
    }
    for (int k = 0; k < info.vtu_pieces; ++k) blocks[b].push_back(body_piece_file(info.bodies[b].name, k));
    for (const auto& file : blocks[b]) run.report().written.push_back(run.dir() / file);
  }
  run.transaction().write("solution.vtm", [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
       << "  <vtkMultiBlockDataSet>\n";
    for (std::size_t b = 0; b < files.size(); ++b) {
      const std::string& name = info.bodies[b].name;
      if (info.vtu_pieces == 0) {
        os << "    <DataSet index=\"" << b << "\" name=\"" << name << "\" file=\"" << files[b] << "\"/>\n";
        continue;
      }
      os << "    <Piece index=\"" << b << "\" name=\"" << name << "\">\n";
      for (std::size_t k = 0; k < blocks[b].size(); ++k)
        os << "      <DataSet index=\"" << k << "\" file=\"" << blocks[b][k] << "\"/>\n";
      os << "    </Piece>\n";
    }
    os << "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
  });
  run.report().written.push_back(run.dir() / "solution.vtm");
}

void write_adapt_steps(OutputRun& run, const RunInfo& info) {
  if (!run.want("adapt.pvd")) return;
  if (!info.adapt_steps) {
    run.report().skipped.push_back(info.adapt.is_null() ? "adapt.pvd: not an adaptive solve"
                                                        : "adapt.pvd: the steps were not kept (the output vtu)");
    return;
  }
  const std::vector<std::string>& steps = *info.adapt_steps;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    run.transaction().write(adapt_step_file(k), [&](std::ostream& os) { os << steps[k]; });
    run.report().written.push_back(run.dir() / adapt_step_file(k));
  }
  run.write("adapt.pvd", [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       << "  <Collection>\n";
    for (std::size_t k = 0; k < steps.size(); ++k)
      os << "    <DataSet timestep=\"" << k << "\" group=\"\" part=\"0\" file=\"" << adapt_step_file(k) << "\"/>\n";
    os << "  </Collection>\n</VTKFile>\n";
  });
}

void OutputRun::write(const std::string& name, const std::function<void(std::ostream&)>& body) {
  if (!want(name)) return;
  tx_.write(name, body);
  report_.written.push_back(dir_ / name);
}

void OutputRun::draw(const std::function<void(std::vector<Figure>&)>& make) {
  std::vector<Figure> figures;  // a figure that cannot be drawn never fails the run
  try {
    make(figures);
    const std::vector<std::string> reasons = draw_figures(tx_.staging(), figures, listed_.figure_formats);
    for (std::size_t i = 0; i < figures.size(); ++i) {
      if (reasons[i].empty()) {
        for (const auto& file : figure_files(figures[i], listed_.figure_formats)) report_.written.push_back(dir_ / file);
      } else {
        report_.skipped.push_back(figures[i].png + ": " + reasons[i]);
        failed_.emplace_back(figures[i].png, reasons[i]);
      }
    }
  } catch (const WriteError& e) {  // a full disk is not a skipped figure
    throw WriteError(e.detail() + "; " + previous_outputs_kept(dir_), (dir_ / fs::path(e.where()).filename()).string());
  } catch (const std::exception& e) {  // each PNG is moved into place atomically: none is half-written
    for (const auto& f : figures)
      if (std::find(report_.written.begin(), report_.written.end(), dir_ / figure_files(f, listed_.figure_formats).front()) ==
          report_.written.end()) {
        report_.skipped.push_back(f.png + ": " + e.what());
        failed_.emplace_back(f.png, e.what());
      }
  }
}

OutputReport OutputRun::finish(const std::function<nlohmann::json(const RunInfo&)>& result_json) {
  report_.warnings = figure_warnings(failed_);
  listed_.warnings.insert(listed_.warnings.end(), report_.warnings.begin(), report_.warnings.end());
  // A figure that could not be made is not in the folder: result.json says so.
  if (want("result.json") && (report_.written.size() != listed_.files.size() || !report_.warnings.empty())) {
    listed_.files.clear();
    for (const auto& f : report_.written) listed_.files.push_back(f.filename().string());
    tx_.write("result.json", [&](std::ostream& os) { os << result_json(listed_).dump(2) << '\n'; });
  }
  // The folder then holds exactly this run's outputs: an earlier run's file of a name this run
  // did not write goes (never anything else).
  report_.removed = tx_.commit();
  return report_;
}

}  // namespace hemivem::app::detail
