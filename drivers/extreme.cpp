#include "extreme.hpp"

#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <memory>
#include <ostream>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include <hemivem/app/engine_pairs.hpp>

#ifndef HEMIVEM_EXTREME_SCENES_DIR
#define HEMIVEM_EXTREME_SCENES_DIR ""
#endif

namespace hemivem::cli {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One (linear, minimizer) pair on one scene, with its largest relative difference of u to a
// converged pair. Its `seconds` exclude the mesh: the shared assembly and condensation and its
// own minimize and back-substitution.
struct Row : PairRun {
  double difference = kNaN;
};

struct SceneReport {
  std::string name, title, mesh;
  std::string refused;      ///< the InputError of a scene that could not be built (e.g. memory)
  int vertices = 0, contact_nodes = 0, unknowns = 0;
  double mesh_seconds = 0.0;
  double margin = kNaN;     ///< the largest margin over the engines (they agree to round-off)
  double max_difference = 0.0;  ///< between converged pairs
  bool unique = false;      ///< margin > 0: the solution is unique, converged pairs must agree
  std::vector<Row> rows;
};

std::string mesh_text(const Scene& s) {
  if (!s.mesh.file.empty()) return s.mesh.file.filename().string();
  std::ostringstream o;
  o << scene_mesh_description(s);
  const auto& d = s.mesh.domain;
  if (!s.mesh.polygon.empty())
    o << " in a polygon of " << s.mesh.polygon.size() << " corners";
  else if (d != std::array<double, 4>{0.0, 1.0, 0.0, 1.0})
    o << " on [" << d[0] << "," << d[1] << "]x[" << d[2] << "," << d[3] << "]";
  return o.str();
}

SceneReport run_scene(const fs::path& file, const ExtremeOptions& o, std::ostream& err) {
  SceneReport rep;
  rep.name = file.stem().string();
  Scene scene = parse_scene(file);
  if (o.tolerance) {
    std::ostringstream v;
    v << std::setprecision(17) << *o.tolerance;
    apply_override(scene, "solver.tolerance=" + v.str());
  }
  rep.title = scene.title;
  rep.mesh = mesh_text(scene);
  const bool progress = o.verbosity >= 1 && !o.json;

  // One mesh and one assembly per scene, condensed once by every linear engine.
  PairRunOptions ro;
  ro.estimate_condition = true;
  ro.input_errors_fail_pairs = true;
  std::string engine;
  ro.done = [&](const PairRun& r) {
    if (!progress || r.pair.linear == engine) return;
    engine = r.pair.linear;
    err << "hemivem check --extreme: " << std::left << std::setw(22) << rep.name << std::setw(12) << engine
        << (r.refused ? "refused" : r.failed ? "engine failed" : "done") << " (" << fixed(r.seconds - r.mesh_seconds, 3)
        << " s)\n";
  };
  PairRuns shared;
  try {
    shared = run_pairs(scene, available_pairs(), ro);
  } catch (const InputError& e) {
    rep.refused = e.what();
    if (progress) err << "hemivem check --extreme: " << rep.name << ": refused: " << e.what() << "\n";
    return rep;
  }
  rep.mesh_seconds = shared.mesh_seconds;
  rep.vertices = shared.vertices;
  // differences relative to max|u| of eigen+ssn (else the largest converged pair)
  const double scale = difference_scale(shared.runs);
  rep.margin = largest_margin(shared.runs);
  rep.unique = rep.margin > 0.0;
  for (auto& run : shared.runs) {
    if (!run.failed) {
      rep.contact_nodes = run.contact_nodes;
      rep.unknowns = run.unknowns;
    }
    Row r;
    static_cast<PairRun&>(r) = std::move(run);
    r.seconds -= r.mesh_seconds;
    rep.rows.push_back(std::move(r));
  }

  for (auto& a : rep.rows) {
    if (a.failed || a.u.size() == 0) continue;
    double m = kNaN;
    for (const auto& b : rep.rows) {
      if (&a == &b || !b.converged || b.u.size() != a.u.size()) continue;
      const double d = max_abs(a.u - b.u) / scale;
      m = std::isnan(m) ? d : std::max(m, d);
      if (a.converged) rep.max_difference = std::max(rep.max_difference, d);
    }
    a.difference = m;
  }
  return rep;
}

std::string cond_text(double rcond) { return rcond > 0.0 ? sci(1.0 / rcond, 1) : "-"; }

std::string margin_text(double m) {
  if (std::isnan(m)) return "-";
  if (std::isinf(m)) return m > 0 ? "inf" : "-inf";
  return sci(m, 1);
}

nlohmann::json scene_json(const SceneReport& s, double agree) {
  nlohmann::json j;
  j["name"] = s.name;
  j["title"] = s.title;
  j["mesh"] = s.mesh;
  if (!s.refused.empty()) {
    j["refused"] = s.refused;
    return j;
  }
  j["vertices"] = s.vertices;
  j["unknowns"] = s.unknowns;
  j["contact_nodes"] = s.contact_nodes;
  j["mesh_seconds"] = s.mesh_seconds;
  j["uniqueness_margin"] = number(s.margin);
  j["unique"] = s.unique;
  j["max_difference"] = s.max_difference;
  j["agree_ok"] = !s.unique || s.max_difference <= agree;
  j["pairs"] = nlohmann::json::array();
  for (const auto& r : s.rows) {
    nlohmann::json p = pair_json(r);
    p.update({{"at_bound", r.at_bound},
              {"stick", r.stick >= 0 ? nlohmann::json(r.stick) : nlohmann::json(nullptr)},
              {"uniqueness_margin", number(r.margin)},
              {"engine_rcond", number(r.rcond)},
              {"condition_estimate", number(r.condition)},
              {"max_difference", number(r.difference)},
              {"seconds", r.seconds},
              {"guarantee_ok", r.guarantee},
              {"guarantee_broken", r.broken}});
    j["pairs"].push_back(p);
  }
  return j;
}

void print_scene(std::ostream& out, const SceneReport& s, double agree) {
  out << "\n== " << s.name << ": " << s.title << "\n   " << s.mesh;
  if (!s.refused.empty()) {
    out << "\n   refused: " << s.refused << "\n";
    return;
  }
  out << ": " << s.vertices << " vertices, " << s.unknowns << " unknowns, " << s.contact_nodes
      << " contact nodes; uniqueness margin " << margin_text(s.margin)
      << (s.unique ? " (unique)" : " (several critical points possible)") << "\n";
  out << "   " << std::left << std::setw(12) << "linear" << std::setw(18) << "minimizer" << std::setw(17) << "status"
      << std::right << std::setw(10) << "primal" << std::setw(10) << "dual" << std::setw(7) << "iter"
      << std::setw(7) << "bound" << std::setw(7) << "stick" << std::setw(10) << "kappa_1" << std::setw(10) << "engine" << std::setw(10) << "max diff" << std::setw(10) << "time [s]" << "  guarantee\n";
  for (const auto& r : s.rows) {
    out << "   " << std::left << std::setw(12) << r.pair.linear << std::setw(18) << r.pair.minimizer << std::setw(17) << r.status
        << std::right << std::setw(10) << sci(r.certificate.primal) << std::setw(10) << sci(r.certificate.dual) << std::setw(7)
        << r.iterations << std::setw(7) << r.at_bound << std::setw(7) << (r.stick >= 0 ? std::to_string(r.stick) : "-")
        << std::setw(10) << sci(r.condition, 1) << std::setw(10) << cond_text(r.rcond) << std::setw(10) << sci(r.difference, 1)
        << std::setw(10) << fixed(r.seconds, 3) << "  " << (r.guarantee ? "ok" : "BROKEN: " + r.broken) << "\n";
    if (r.failed) out << "      " << (r.refused ? "refused: " : "") << r.message << "\n";
  }
  int converged = 0, refused = 0;
  for (const auto& r : s.rows) converged += r.converged, refused += r.refused;
  out << "   " << converged << " of " << s.rows.size() << " pairs converged"
      << (refused ? " (" + std::to_string(refused) + " on the full-space route refused the scene)" : std::string())
      << "; largest difference between converged pairs " << sci(s.max_difference);
  if (s.unique && s.max_difference > agree) out << " > " << sci(agree) << " (DISAGREE)";
  out << "\n";
}

/// The *.toml scenes of the folder, sorted, kept to those --only names (each of which must be
/// there).
std::vector<fs::path> extreme_scenes(const fs::path& dir, const std::vector<std::string>& only) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == ".toml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const auto& name : only)
    if (std::none_of(files.begin(), files.end(), [&](const fs::path& f) { return f.stem() == name; })) {
      std::string names;
      for (const auto& f : files) names += (names.empty() ? "" : ", ") + f.stem().string();
      throw InputError("no scene '" + name + "' in " + dir.string() + "; expected one of: " + names, "--only");
    }
  if (!only.empty())
    std::erase_if(files, [&](const fs::path& f) { return std::find(only.begin(), only.end(), f.stem()) == only.end(); });
  if (files.empty()) throw InputError("no *.toml scene in the folder", dir.string());
  return files;
}

/// One line per scene: how many pairs converged, the margin, the range of kappa_1, the
/// largest difference and the slowest pair's time.
void print_summary(std::ostream& out, const std::vector<SceneReport>& reports) {
  out << "\n  summary\n  " << std::left << std::setw(24) << "scene" << std::right << std::setw(11) << "converged"
      << std::setw(11) << "margin" << std::setw(20) << "kappa_1" << std::setw(11) << "max diff" << std::setw(11)
      << "time [s]" << "\n";
  for (const auto& s : reports) {
    out << "  " << std::left << std::setw(24) << s.name << std::right;
    if (!s.refused.empty()) {
      out << "  refused (see above)\n";
      continue;
    }
    int converged = 0;
    double lo = kNaN, hi = kNaN, worst = 0.0;
    for (const auto& r : s.rows) {
      converged += r.converged;
      worst = std::max(worst, r.seconds);
      if (r.condition > 0.0) {
        const double c = r.condition;
        lo = std::isnan(lo) ? c : std::min(lo, c);
        hi = std::isnan(hi) ? c : std::max(hi, c);
      }
    }
    std::ostringstream conv, cond;
    conv << converged << "/" << s.rows.size();
    cond << (std::isnan(lo) ? "-" : sci(lo, 1) + (hi > lo * 1.5 ? ".." + sci(hi, 1) : ""));
    out << std::setw(11) << conv.str() << std::setw(11) << margin_text(s.margin) << std::setw(20) << cond.str()
        << std::setw(11) << sci(s.max_difference) << std::setw(11) << fixed(worst + s.mesh_seconds, 2) << "\n";
  }
}

/// The report of `hemivem check --extreme --json` (schema hemivem-stability/2).
nlohmann::json extreme_json(const fs::path& dir, double agree, const std::vector<SceneReport>& reports, bool broken,
                            int code) {
  nlohmann::json j;
  j["schema"] = "hemivem-stability/2";
  j["version"] = HEMIVEM_VERSION;
  j["scenes_folder"] = fs::absolute(dir).lexically_normal().string();
  j["agree"] = agree;
  j["scenes"] = nlohmann::json::array();
  for (const auto& s : reports) j["scenes"].push_back(scene_json(s, agree));
  j["guarantees_ok"] = !broken;
  j["exit_code"] = code;
  return j;
}

}  // namespace

int run_check_extreme(const ExtremeOptions& o, std::ostream& out, std::ostream& err) {
  if (!(o.agree > 0.0)) throw InputError("must be > 0", "--agree");
  const fs::path dir = o.scenes.empty() ? fs::path(HEMIVEM_EXTREME_SCENES_DIR) : fs::path(o.scenes);
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(dir, ec))
    throw InputError("not a folder of scenes" + std::string(o.scenes.empty() ? " (pass one with --scenes)" : ""),
                     dir.empty() ? "--scenes" : dir.string());
  const std::vector<fs::path> files = extreme_scenes(dir, o.only);

  std::vector<SceneReport> reports;
  for (const auto& f : files) reports.push_back(run_scene(f, o, err));

  bool broken = false, disagree = false;
  for (const auto& s : reports) {
    for (const auto& r : s.rows) broken |= !r.guarantee;
    disagree |= s.unique && s.max_difference > o.agree;
  }
  const int code = broken ? kInternalError : disagree ? kDisagreement : kSuccess;

  if (o.json) {
    out << extreme_json(dir, o.agree, reports, broken, code).dump(2) << "\n";
    return code;
  }
  if (o.verbosity < 1) return code;
  out << "hemivem check --extreme: " << reports.size() << " scenes from " << dir.string()
      << "\n  every built pair of engines (the Krylov engines with ssn on the full-space route, nothing factorized);"
      << "\n  differences are max|u_a - u_b| / max|u_ref| (u_ref: eigen+ssn);"
      << "\n  kappa_1: estimate of the 1-norm condition number of the factorized matrix (A22; A without contact),"
      << "\n  the same method for every engine ('-' on the full-space route); engine: 1 / the engine's own reciprocal"
      << "\n  condition estimate, '-' where it gives none; bound: contact nodes at a bound of the constraint; stick:"
      << "\n  contact nodes that stick (friction); guarantee: a converged pair has finite u and a feasible point"
      << " (recomputed)\n";
  for (const auto& s : reports) print_scene(out, s, o.agree);
  print_summary(out, reports);
  out << "\n  verdict   ";
  if (code == kSuccess) out << "no guarantee broken; converged pairs agree within " << sci(o.agree) << " wherever the solution is unique\n";
  else if (code == kInternalError) out << "a guarantee was broken (exit " << code << ")\n";
  else out << "converged pairs disagree on a scene with a unique solution (exit " << code << ")\n";
  return code;
}

}  // namespace hemivem::cli
