// The subcommands of the hemivem tool. Each returns the process exit code (common.hpp) and
// lets InputError / NumericalError escape for main() to report.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace hemivem::cli {

struct SolveOptions {
  std::string scene;                    ///< scene file; empty: the embedded Example 4.1
  std::optional<std::string> mesh;      ///< generator name or a .poly2d / .msh path
  std::optional<int> n;
  std::optional<std::string> linear;
  std::optional<std::string> minimizer;
  std::optional<double> tolerance;
  std::vector<std::string> set;         ///< --set key=value, in order
  std::string out = "out/solve";
  std::string export_reduced;           ///< folder for the reduced problem, empty: none
  bool json = false;                    ///< result.json on stdout instead of the summary
  int verbosity = 1;                    ///< 0 quiet, 1 summary, 2 summary and iterations
};

/// hemivem solve [SCENE.toml]: scene -> mesh -> assembly -> condensation -> minimizer ->
/// back-substitution -> the output folder. Exit 0 when converged, kNotConverged otherwise
/// (outputs are still written and marked).
int run_solve(const SolveOptions& options, std::ostream& out, std::ostream& err);

struct MinimizeOptions {
  std::string folder;                   ///< a reduced problem written by --export-reduced
  std::string minimizer = "ssn";
  std::string law;                      ///< replaces law.txt when given
  double tolerance = 1e-10;
  bool json = false;
  int verbosity = 1;
};

/// hemivem minimize DIR: the same reduced problem, from files, for any minimizer.
int run_minimize(const MinimizeOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
