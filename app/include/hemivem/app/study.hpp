// The convergence study of the paper's Table 1 (docs/table1.md).
//
// The scene is solved on N x N squares for each N and for a reference N that every N divides;
// each coarse solution is prolonged exactly to the reference mesh (on axis-aligned rectangles
// the lowest-order VEM functions are bilinear), and the error is the exact energy of the
// bilinear difference there: ||v||_E = (1/sqrt 2) (sigma(v), eps(v))^(1/2), relative error
// ||u_ref - P u_h||_E / ||u_ref||_E. `hemivem study` prints it and writes study.csv,
// study.json and study.png (write_study); Python's hemivem.study returns it.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/figures.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// One solve of the study, as it is done (for progress).
struct StudySolveInfo {
  int n = 0;
  int vertices = 0;
  std::string status;
  int iterations = 0;
  double seconds = 0.0;
};

struct StudyOptions {
  std::vector<int> n{4, 8, 16, 32, 64};  ///< the coarse sizes N (sorted and made distinct)
  int ref = 256;                         ///< the reference N, a multiple of every N
  /// The overrides applied to the scene, recorded in study.json (the scene already has them).
  std::vector<std::string> overrides;
  std::string n_key = "n", ref_key = "ref";  ///< where a bad size or reference size is reported
  std::function<void(const StudySolveInfo&)> solved;  ///< called after each solve, the reference first
};

/// One coarse size: h, the relative energy error and its rate against the previous size, the
/// paper's and the independent implementation's errors (Example 4.1 only), the solve's
/// relative a posteriori estimate and its effectivity eta / ||u_ref - P u_h||_E.
struct StudyRow {
  int n = 0;
  double h = 0.0;
  double error = 0.0;
  std::optional<double> rate, paper, independent;
  std::optional<double> estimate;
  std::optional<double> effectivity;
  bool converged = false;
  int iterations = 0;
  double seconds = 0.0;
};

struct StudyResult {
  int ref = 0;                     ///< the reference N
  double ref_norm = 0.0;           ///< ||u_ref||_E
  bool ref_converged = false;
  int ref_iterations = 0;
  bool converged = false;          ///< every solve, the reference included, converged
  bool references = false;         ///< Example 4.1: the rows carry docs/table1.md's values
  std::vector<StudyRow> rows;      ///< coarse to fine
};

/// The coarse sizes of `options`, sorted and distinct, after checking that the scene is on
/// squares (InputError at mesh.generator) and that every N is positive and divides the
/// reference N (InputError at options.n_key / options.ref_key). Nothing is solved.
std::vector<int> study_sizes(const Scene& scene, const StudyOptions& options);

/// Solves `scene` on the reference squares and on each coarse size and measures the errors.
/// Never prints. InputErrors of study_sizes, and when the reference solution is zero.
StudyResult run_study(const Scene& scene, const StudyOptions& options);

/// study.json (schema hemivem-study/2).
nlohmann::json study_json(const Scene& scene, const StudyOptions& options, const StudyResult& result);

/// The note on the paper's column that Example 4.1's study prints and writes.
std::string study_note();

/// What write_study wrote: the files' names, why study.png was skipped (empty: drawn), the
/// figure gnuplot could not draw as a warning (figure_warnings of figures.hpp; study.json's
/// "warnings"), which the command prints on stderr, and study.json's content as written.
struct StudyFiles {
  std::vector<std::string> written;
  std::string skipped;
  std::vector<std::string> warnings;
  nlohmann::json json;
};

/// study.csv, study.json (with "files", the files written, and "warnings") and study.png (in
/// the formats of the scene's output.figure_format, when gnuplot draws it) into `dir`, the
/// folder changed at once (OutputTransaction).
StudyFiles write_study(const std::filesystem::path& dir, const Scene& scene, const StudyOptions& options,
                       const StudyResult& result);

/// One mesh size of the study's figure: h, the relative error, and the paper's and the
/// independent implementation's errors where docs/table1.md has them.
struct StudyPoint {
  double h = 0.0;
  double error = 0.0;
  std::optional<double> paper, independent;
};

/// study.png: the relative error (%) against h on log axes, an O(h) slope through the first
/// (coarsest) point, and with `with_references` the paper's and the independent values; the
/// title names the reference N.
Figure study_figure(const std::vector<StudyPoint>& points, bool with_references, int ref);

}  // namespace hemivem::app
