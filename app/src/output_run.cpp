// The writing of one run's output folder (output_run.hpp).
#include "output_run.hpp"

#include <hemivem/error.hpp>
#include <hemivem/support/atomic_file.hpp>

#include "path_outputs.hpp"

#include <algorithm>
#include <ostream>

namespace hemivem::app::detail {

namespace fs = std::filesystem;

namespace {

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The names a run may own: its own, the other dimension's, an earlier path's frames, its frames.
std::vector<std::string> owned_names(const fs::path& dir, const std::vector<std::string>& known,
                                     const std::vector<std::string>& others, const std::vector<std::string>& frames) {
  std::vector<std::string> owned = known;
  for (const auto& name : others)
    if (!contains(owned, name)) owned.push_back(name);
  for (const auto& name : frame_files_in(dir)) owned.push_back(name);
  owned.insert(owned.end(), frames.begin(), frames.end());
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
    : dir_(dir), wanted_(wanted), tx_(dir, owned_names(dir, known, others, frames)), listed_(info) {
  listed_.files.clear();
  for (const auto& k : known)
    if (want(k)) listed_.files.push_back(k);
  if (want("solution.pvd")) listed_.files.insert(listed_.files.end(), frames.begin(), frames.end());
}

bool OutputRun::want(const std::string& name) const { return contains(wanted_, name); }

void OutputRun::write(const std::string& name, const std::function<void(std::ostream&)>& body) {
  if (!want(name)) return;
  tx_.write(name, body);
  report_.written.push_back(dir_ / name);
}

void OutputRun::draw(const std::function<void(std::vector<Figure>&)>& make) {
  std::vector<Figure> figures;  // a figure that cannot be drawn never fails the run
  try {
    make(figures);
    const std::vector<std::string> reasons = draw_figures(tx_.staging(), figures);
    for (std::size_t i = 0; i < figures.size(); ++i) {
      if (reasons[i].empty()) {
        report_.written.push_back(dir_ / figures[i].png);
      } else {
        report_.skipped.push_back(figures[i].png + ": " + reasons[i]);
        failed_.emplace_back(figures[i].png, reasons[i]);
      }
    }
  } catch (const WriteError& e) {  // a full disk is not a skipped figure
    throw WriteError(e.detail() + "; " + previous_outputs_kept(dir_), (dir_ / fs::path(e.where()).filename()).string());
  } catch (const std::exception& e) {  // each PNG is moved into place atomically: none is half-written
    for (const auto& f : figures)
      if (std::find(report_.written.begin(), report_.written.end(), dir_ / f.png) == report_.written.end()) {
        report_.skipped.push_back(f.png + ": " + e.what());
        failed_.emplace_back(f.png, e.what());
      }
  }
}

namespace {

/// One warning per reason, naming the figures it kept from being drawn:
/// "figure not drawn: u_nu.png, deformed.png: gnuplot failed (status 1): ...".
std::vector<std::string> figure_warnings(const std::vector<std::pair<std::string, std::string>>& failed) {
  std::vector<std::pair<std::string, std::string>> by_reason;  // names, reason; in the order drawn
  for (const auto& [name, reason] : failed) {
    auto same = std::find_if(by_reason.begin(), by_reason.end(), [&](const auto& r) { return r.second == reason; });
    if (same == by_reason.end()) by_reason.emplace_back(name, reason);
    else same->first += ", " + name;
  }
  std::vector<std::string> out;
  for (const auto& [names, reason] : by_reason) out.push_back("figure not drawn: " + names + ": " + reason);
  return out;
}

}  // namespace

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
