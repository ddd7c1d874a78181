// hemivem study: the convergence study of the paper's Table 1 (docs/table1.md), computed by
// hemivem::app::run_study (hemivem/app/study.hpp); here its flags, table and exit code.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <hemivem/app/study.hpp>

namespace hemivem::cli {

using namespace hemivem::app;

struct StudyOptions {
  std::string scene;                   ///< scene file; empty: the embedded Example 4.1
  std::vector<int> n{4, 8, 16, 32, 64};
  int ref = 256;
  std::vector<std::string> set;        ///< --set key=value, in order, applied to every solve
  std::string out = "out/study";
  bool json = false;                   ///< study.json on stdout instead of the table
  int verbosity = 1;                   ///< 0 quiet, 1 table and a progress line per solve
};

/// hemivem study [SCENE.toml]: writes study.csv, study.json and study.png (when gnuplot is
/// found) into options.out. Exit 0 when every solve converged, kNotConverged otherwise (the
/// outputs are still written and marked); InputError for a scene that is not on squares or
/// an N that does not divide the reference N.
int run_study(const StudyOptions& options, std::ostream& out, std::ostream& err);

}  // namespace hemivem::cli
