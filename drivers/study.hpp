// hemivem study: the convergence study of the paper's Table 1 (docs/table1.md).
//
// The scene is solved on N x N squares for each N and for a reference N that every N divides;
// each coarse solution is prolonged exactly to the reference mesh (on axis-aligned rectangles
// the lowest-order VEM functions are bilinear), and the error is the exact energy of the
// bilinear difference there: ||v||_E = (1/sqrt 2) (sigma(v), eps(v))^(1/2), relative error
// ||u_ref - P u_h||_E / ||u_ref||_E.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <hemivem/app/figures.hpp>

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

/// One mesh size of the study: h, the relative error, and the paper's and the independent
/// implementation's errors where docs/table1.md has them.
struct StudyPoint {
  double h = 0.0;
  double error = 0.0;
  std::optional<double> paper, independent;
};

/// study.png: the relative error (%) against h on log axes, an O(h) slope through the first
/// (coarsest) point, and with `with_references` the paper's and the independent values; the
/// title names the reference N.
Figure study_figure(const std::vector<StudyPoint>& points, bool with_references, int ref);

}  // namespace hemivem::cli
