// Pieces shared by the subcommands of the hemivem tool.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include <hemivem/app/format.hpp>
#include <hemivem/app/launcher.hpp>

#include <nlohmann/json.hpp>

namespace hemivem::cli {

// The command stands on the application library.
using namespace hemivem::app;

/// Exit codes of the hemivem command.
enum ExitCode : int {
  kSuccess = 0,
  kInputError = 2,       ///< bad flags, files or parameters
  kNotConverged = 3,     ///< a solve finished without reaching its tolerance (results are written, marked)
  kBackendFailure = 4,   ///< an engine failed (e.g. a matrix that is not positive definite)
  kInternalError = 5,
  kDisagreement = 6,     ///< hemivem check: two converged engine pairs differ by more than --agree
};


/// True on the process that prints and writes: rank 0 of the launcher and, once a mumps-mpi
/// engine exists, of that engine.
bool reporting_process();

/// Arms what an interrupted run says: on SIGINT or SIGTERM the command prints "hemivem:
/// interrupted by SIGINT: DIR keeps its previous outputs" (or "no outputs were written to DIR";
/// "DIR holds this run's outputs" once they are in place) on stderr, then ends by the signal
/// (its exit status). Called once the output folder `dir` is known, on the process that reports.
void say_what_an_interruption_keeps(const std::filesystem::path& dir);

/// `s` as a TOML basic string: quoted, with '"' and '\\' escaped.
std::string toml_string(const std::string& s);

/// The override that --figures FORMATS (comma-separated, "png,pdf") stands for:
/// output.figure_format=["png", "pdf"]; the scene's reader checks the names.
std::string figure_format_override(const std::string& formats);

/// The mesh sizes of a comma-separated list such as "4,8,16" (a flag's value): InputError at
/// `flag` naming the bad entry and its place when an entry is empty ("4,,8"), not an integer or
/// not in [1, 10000000].
std::vector<int> parse_sizes(const std::string& text, const std::string& flag);

}  // namespace hemivem::cli
