#include "study.hpp"

#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include <hemivem/app/outputs.hpp>

namespace hemivem::cli {

namespace {

std::string percent(const std::optional<double>& v, int precision = 2) {
  if (!v) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << 100.0 * *v << " %";
  return s.str();
}

std::string h_text(int n, const std::array<double, 4>& d) {
  if (d[0] == 0.0 && d[1] == 1.0 && d[2] == 0.0 && d[3] == 1.0) return "1/" + std::to_string(n);
  std::ostringstream s;
  s << std::setprecision(4) << std::max(d[1] - d[0], d[3] - d[2]) / n;
  return s.str();
}

void print_study(std::ostream& out, const Scene& scene, const StudyOptions& o, const app::StudyResult& result,
                 const app::StudyFiles& files) {
  const std::vector<app::StudyRow>& rows = result.rows;
  const std::vector<std::string>& written = files.written;
  out << "hemivem study: " << scene.title << " (" << scene.source << "), squares, reference N = " << o.ref << ", "
      << to_string(scene.material.model) << ", stabilization " << to_string(scene.material.stabilization) << "\n"
      << "  relative energy error ||u_ref - P u_h||_E / ||u_ref||_E (exact, bilinear, on the reference mesh);\n"
      << "  estimate eta / ||u_h||_E (a posteriori), effectivity eta / ||u_ref - P u_h||_E\n\n";
  out << std::right << std::setw(8) << "h" << std::setw(6) << "N" << std::setw(11) << "error" << std::setw(7) << "rate"
      << std::setw(11) << "paper" << std::setw(14) << "independent" << std::setw(11) << "estimate" << std::setw(13)
      << "effectivity" << "\n";
  for (const auto& r : rows) {
    std::ostringstream rate;
    if (r.rate) rate << std::fixed << std::setprecision(2) << *r.rate;
    else rate << "-";
    out << std::setw(8) << h_text(r.n, scene.mesh.domain) << std::setw(6) << r.n << std::setw(11) << percent(r.error)
        << std::setw(7) << rate.str() << std::setw(11) << percent(r.paper, r.n == 64 ? 3 : 2) << std::setw(14)
        << percent(r.independent) << std::setw(11) << percent(r.estimate) << std::setw(13)
        << (r.effectivity ? fixed(*r.effectivity, 2) : std::string("-")) << (r.converged ? "" : "  (not converged)") << "\n";
  }
  out << "\n";
  if (result.references) out << "  note: " << app::study_note() << ".\n";
  out << "  wrote " << o.out << "/ (";
  for (std::size_t i = 0; i < written.size(); ++i) out << (i ? ", " : "") << written[i];
  out << ")\n";
  if (!files.skipped.empty()) out << "  skipped study.png: " << files.skipped << "\n";
}

}  // namespace

int run_study(const StudyOptions& o, std::ostream& out, std::ostream& err) {
  Scene scene = o.scene.empty() ? default_scene() : parse_scene(o.scene);
  apply_overrides(scene, o.set);
  app::StudyOptions so;
  so.n = o.n;
  so.ref = o.ref;
  so.overrides = o.set;
  so.n_key = "--n";
  so.ref_key = "--ref";
  (void)app::study_sizes(scene, so);
  check_output_folder(o.out);
  say_what_an_interruption_keeps(o.out);
  if (o.verbosity >= 1)
    so.solved = [&](const app::StudySolveInfo& s) {
      err << "hemivem study: N = " << s.n << ": " << s.vertices << " vertices, " << s.status << " (" << s.iterations
          << " iterations), " << std::fixed << std::setprecision(2) << s.seconds << std::defaultfloat << " s\n";
    };
  const app::StudyResult result = app::run_study(scene, so);
  const app::StudyFiles files = app::write_study(o.out, scene, so, result);
  for (const auto& w : files.warnings) err << "hemivem: warning: " << w << "\n";  // a figure not drawn
  if (o.json)
    out << files.json.dump(2) << "\n";
  else if (o.verbosity >= 1)
    print_study(out, scene, o, result, files);
  return result.converged && result.ref_converged ? kSuccess : kNotConverged;
}

}  // namespace hemivem::cli
