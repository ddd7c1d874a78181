// The writing of one run's output folder, shared by the writers of plane and solid solves
// (private to hemivem::app): the names the run owns, the transaction, the files wanted,
// result.json's list of files, the figures, the history.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/text_writer.hpp>
#include <hemivem/contact/solver.hpp>
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

/// InputError for a name of `wanted` that is not in `known` (`what`: "", or " of a
/// three-dimensional solve"), listing the known names.
void require_known_outputs(const std::vector<std::string>& wanted, const std::vector<std::string>& known,
                           const std::string& what);

/// One run's folder: the files are written into a transaction that owns `known`, `others` (the
/// other dimension's names), an earlier path's frames and `frames` (this run's), and that
/// commit() makes the folder at once. result.json lists the files wanted, in the order of
/// `known`, then the frames when solution.pvd is wanted.
class OutputRun {
 public:
  OutputRun(const std::filesystem::path& dir, const std::vector<std::string>& known, const std::vector<std::string>& others,
            const std::vector<std::string>& wanted, const RunInfo& info, const std::vector<std::string>& frames);

  bool want(const std::string& name) const;
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
  /// result.json again when a file could not be made (it lists what was written), then the
  /// commit: the folder holds exactly this run's outputs.
  OutputReport finish(const std::function<nlohmann::json(const RunInfo&)>& result_json);

 private:
  std::filesystem::path dir_;
  std::vector<std::string> wanted_;
  OutputTransaction tx_;
  OutputReport report_;
  RunInfo listed_;
};

}  // namespace hemivem::app::detail
