#include "outputs.hpp"
#include "vtu.hpp"

#include "common.hpp"

#include <hemivem/assembly.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <array>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <random>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>

#include <unistd.h>

namespace hemivem::cli {

namespace fs = std::filesystem;

namespace {

/// A number for JSON: non-finite values become null (JSON has no inf or NaN).
double timing(const ContactSolution& s, const std::string& stage) {
  const auto it = s.timings.find(stage);
  return it == s.timings.end() ? 0.0 : it->second;
}

void full_precision(std::ostream& os) { os << std::setprecision(17); }

/// Text for large tables, written through a buffer: each number as the shortest text that
/// reads back as exactly the same double (std::to_chars).
class TextWriter {
 public:
  explicit TextWriter(std::ostream& os) : os_(os) { buffer_.reserve(kFlush + 64); }
  TextWriter(const TextWriter&) = delete;
  TextWriter& operator=(const TextWriter&) = delete;
  ~TextWriter() { flush(); }

  TextWriter& operator<<(double x) {
    if (!std::isfinite(x)) return *this << (std::isnan(x) ? "nan" : x > 0 ? "inf" : "-inf");
    char text[32];
    const auto r = std::to_chars(text, text + sizeof text, x);
    return append(std::string_view(text, static_cast<std::size_t>(r.ptr - text)));
  }
  TextWriter& operator<<(long long k) {
    char text[24];
    const auto r = std::to_chars(text, text + sizeof text, k);
    return append(std::string_view(text, static_cast<std::size_t>(r.ptr - text)));
  }
  TextWriter& operator<<(int k) { return *this << static_cast<long long>(k); }
  TextWriter& operator<<(char c) { return append(std::string_view(&c, 1)); }
  TextWriter& operator<<(std::string_view text) { return append(text); }
  TextWriter& operator<<(const char* text) { return append(std::string_view(text)); }
  TextWriter& operator<<(const std::string& text) { return append(text); }

  void flush() {
    os_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kFlush = std::size_t{1} << 20;
  TextWriter& append(std::string_view text) {
    buffer_.append(text);
    if (buffer_.size() >= kFlush) flush();
    return *this;
  }
  std::ostream& os_;
  std::string buffer_;
};

void write_contact_csv(std::ostream& stream, const ContactSolution& s) {
  TextWriter os(stream);
  os << "vertex,x,y,u_nu,law_force,reaction,pressure,state,gap,nx,ny\n";
  for (const auto& n : s.contact)
    os << n.vertex << ',' << n.x.x() << ',' << n.x.y() << ',' << n.u_nu << ',' << n.law_force << ',' << n.reaction
       << ',' << n.pressure() << ',' << n.state << ',' << n.gap << ',' << n.normal.x() << ',' << n.normal.y() << '\n';
}

void write_displacement_csv(std::ostream& stream, const Mesh& mesh, const Eigen::VectorXd& u) {
  TextWriter os(stream);
  os << "vertex,x,y,ux,uy\n";
  for (int v = 0; v < mesh.num_vertices(); ++v)
    os << v << ',' << mesh.vertex(v).x() << ',' << mesh.vertex(v).y() << ',' << u(2 * v) << ',' << u(2 * v + 1)
       << '\n';
}

void write_history_csv(std::ostream& stream, const ContactSolution& s) {
  TextWriter os(stream);
  os << "iteration,reduced_objective,primal,dual,active,seconds\n";
  for (const auto& r : s.minimizer.history)
    os << r.iteration << ',' << r.objective << ',' << r.primal << ',' << r.dual << ',' << r.active << ',' << r.seconds
       << '\n';
}

// ---- plots ----------------------------------------------------------------------

}  // namespace

/// The full path of `program` found on PATH, or empty.
fs::path find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path candidate = fs::path(dir) / program;
    if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate)) return candidate;
  }
  return {};
}

namespace {

/// A single-quoted string for the shell (and for gnuplot, which takes '...' with '' as a quote).
std::string shell_quote(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return r + "'";
}

}  // namespace

std::string gnuplot_quote(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += c == '\'' ? std::string("''") : std::string(1, c);
  return r + "'";
}

namespace {

/// A private temporary folder removed on destruction.
class TempDir {
 public:
  TempDir() {
    static std::atomic<unsigned> counter{0};
    std::random_device rd;
    const fs::path base = fs::temp_directory_path();
    for (int attempt = 0; attempt < 100; ++attempt) {
      const fs::path p = base / ("hemivem-plots-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
                                 "-" + std::to_string(rd()));
      std::error_code ec;
      if (fs::create_directory(p, ec)) {
        path_ = p;
        return;
      }
    }
    throw InputError("cannot create a temporary folder", base.string());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

void write_plain(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  std::ofstream os(path);
  if (!os) throw InputError("cannot write", path.string());
  write(os);
  os.flush();
  if (!os) throw InputError("cannot write", path.string());
}

/// Contact nodes ordered along Gamma_3, chained through the boundary edges joining them;
/// each chain is one polyline, with its arc length s from its first node.
struct ContactPoint {
  double s = 0.0;
  const ContactNode* node = nullptr;
};
std::vector<std::vector<ContactPoint>> contact_chains(const Mesh& mesh, const ContactSolution& sol) {
  std::map<int, const ContactNode*> by_vertex;
  for (const auto& n : sol.contact) by_vertex[n.vertex] = &n;
  std::map<int, std::vector<int>> next;
  for (const auto& [v0, v1] : contact_lines(mesh, sol)) {
    next[v0].push_back(v1);
    next[v1].push_back(v0);
  }
  // start points: chain ends (degree <= 1) first, sorted by (x, y) so the output is stable
  std::vector<int> starts;
  for (const auto& [v, n] : by_vertex)
    if (next[v].size() <= 1) starts.push_back(v);
  auto lexi = [&](int a, int b) {
    const Vec2& pa = mesh.vertex(a);
    const Vec2& pb = mesh.vertex(b);
    return pa.x() != pb.x() ? pa.x() < pb.x() : pa.y() < pb.y();
  };
  std::sort(starts.begin(), starts.end(), lexi);
  for (const auto& [v, n] : by_vertex) starts.push_back(v);  // closed loops

  std::set<int> seen;
  std::vector<std::vector<ContactPoint>> chains;
  for (int start : starts) {
    if (seen.count(start)) continue;
    std::vector<ContactPoint> chain;
    int v = start;
    double s = 0.0;
    int prev = -1;
    while (v >= 0 && !seen.count(v)) {
      seen.insert(v);
      if (prev >= 0) s += (mesh.vertex(v) - mesh.vertex(prev)).norm();
      chain.push_back({s, by_vertex[v]});
      int following = -1;
      for (int w : next[v])
        if (!seen.count(w)) {
          following = w;
          break;
        }
      prev = v;
      v = following;
    }
    chains.push_back(std::move(chain));
  }
  return chains;
}

}  // namespace

/// Runs gnuplot on `script`; empty on success, else the reason.
std::string run_gnuplot(const fs::path& gnuplot, const fs::path& script, const fs::path& log) {
  const std::string command =
      shell_quote(gnuplot.string()) + " " + shell_quote(script.string()) + " >" + shell_quote(log.string()) + " 2>&1";
  const int rc = std::system(command.c_str());
  if (rc == 0) return {};
  std::ifstream in(log);
  std::string first_line;
  std::getline(in, first_line);
  return "gnuplot failed (status " + std::to_string(rc) + ")" + (first_line.empty() ? "" : ": " + first_line);
}

namespace {

/// Moves a finished file from the temporary folder into place (copy + atomic rename when the
/// two are on different file systems).
void move_into_place(const fs::path& from, const fs::path& to) {
  write_atomically(to, [&](std::ostream& os) {
    std::ifstream in(from, std::ios::binary);
    if (!in) throw InputError("cannot read", from.string());
    os << in.rdbuf();
  });
}

}  // namespace

bool is_png(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in.gcount() == 8 && std::string(sig, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}

namespace {

/// The most edges deformed.png draws one by one (a 1000 x 700 picture).
constexpr std::size_t kMaxDrawnEdges = 100000;

void make_plots(const fs::path& dir, const Mesh& mesh, const ContactSolution& sol, bool want_unu, bool want_deformed,
                OutputReport& report) {
  auto skip = [&](const std::string& reason) {
    if (want_unu) report.skipped.push_back("u_nu.png: " + reason);
    if (want_deformed) report.skipped.push_back("deformed.png: " + reason);
  };
  const fs::path gnuplot = find_on_path("gnuplot");
  if (gnuplot.empty()) return skip("gnuplot not found on PATH");
  if (want_unu && sol.contact.empty()) {
    report.skipped.push_back("u_nu.png: no contact boundary");
    want_unu = false;
  }
  if (!want_unu && !want_deformed) return;

  TempDir tmp;
  const fs::path& t = tmp.path();
  std::ostringstream script;
  // pngcairo when built in, else the gd-based png terminal
  script << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) { set terminal pngcairo size 1000,700 enhanced } "
            "else { set terminal png size 1000,700 }\n";
  if (want_unu) {
    write_plain(t / "u_nu.dat", [&](std::ostream& os) {
      full_precision(os);
      os << "# s x y u_nu pressure gap\n";
      for (const auto& chain : contact_chains(mesh, sol)) {
        for (const auto& p : chain)
          os << p.s << ' ' << p.node->x.x() << ' ' << p.node->x.y() << ' ' << p.node->u_nu << ' '
             << p.node->pressure() << ' ' << p.node->gap << '\n';
        os << "\n\n";  // a new data block per chain
      }
    });
    script << "set output " << gnuplot_quote((t / "u_nu.png").string()) << "\n"
           << "set title 'normal displacement and contact pressure along {/Symbol G}_3'\n"
           << "set xlabel 'arc length s along {/Symbol G}_3'\n"
           << "set ylabel 'u_{/Symbol n}, gap g'\n"
           << "set y2label 'contact pressure (compression > 0)'\n"
           << "set ytics nomirror\nset y2tics\nset grid\nset key outside top center horizontal\n"
           << "plot " << gnuplot_quote((t / "u_nu.dat").string())
           << " using 1:4 with linespoints pt 7 ps 0.6 lw 2 lc rgb '#1f77b4' title 'u_{/Symbol n}', "
           << "'' using 1:6 with lines dt 2 lw 1.5 lc rgb '#555555' title 'gap g', "
           << "'' using 1:5 axes x1y2 with linespoints pt 6 ps 0.5 lw 1.5 lc rgb '#d62728' title 'pressure'\n"
           << "unset output\nreset\n";
  }
  if (want_deformed) {
    // magnify the displacement so that its largest value shows as 10% of the domain's size
    const Rectangle box = mesh.bounding_box();
    const double size = std::hypot(box.width(), box.height());
    double umax = 0.0;
    for (int v = 0; v < mesh.num_vertices(); ++v) umax = std::max(umax, std::hypot(sol.u(2 * v), sol.u(2 * v + 1)));
    const double scale = umax > 0.0 && std::isfinite(umax) ? std::max(1.0, 0.1 * size / umax) : 1.0;
    auto deformed = [&](int v) -> Vec2 { return mesh.vertex(v) + scale * Vec2(sol.u(2 * v), sol.u(2 * v + 1)); };
    auto magnitude = [&](int v) { return std::hypot(sol.u(2 * v), sol.u(2 * v + 1)); };
    // Edges finer than the picture's pixels only cost time: a mesh with more edges than
    // kMaxDrawnEdges is drawn by its boundary.
    const bool boundary_only = mesh.edges().size() > kMaxDrawnEdges;
    write_plain(t / "edges.dat", [&](std::ostream& stream) {
      TextWriter os(stream);
      os << "# x y |u| (deformed edges, one block each)\n";
      auto put = [&](const MeshEdge& e) {
        const Vec2 a = deformed(e.v0), b = deformed(e.v1);
        os << a.x() << ' ' << a.y() << ' ' << magnitude(e.v0) << '\n'
           << b.x() << ' ' << b.y() << ' ' << magnitude(e.v1) << "\n\n";
      };
      if (boundary_only)
        for (int e : mesh.boundary_edges()) put(mesh.edges()[static_cast<std::size_t>(e)]);
      else
        for (const auto& e : mesh.edges()) put(e);
    });
    write_plain(t / "contact.dat", [&](std::ostream& os) {
      full_precision(os);
      os << "# x y (deformed contact nodes)\n";
      for (const auto& n : sol.contact) {
        const Vec2 p = deformed(n.vertex);
        os << p.x() << ' ' << p.y() << '\n';
      }
    });
    std::ostringstream title;
    title << (boundary_only ? "deformed boundary" : "deformed mesh") << " (displacement x " << std::setprecision(3)
          << scale << "), colour: |u|";
    if (boundary_only) title << "; " << mesh.edges().size() << " edges are finer than the picture";
    script << "set output " << gnuplot_quote((t / "deformed.png").string()) << "\n"
           << "set title " << gnuplot_quote(title.str()) << "\n"
           << "set size ratio -1\nset xlabel 'x'\nset ylabel 'y'\nunset key\n"
           << "set palette rgbformulae 33,13,10\nset cblabel '|u|'\n";
    script << "plot " << gnuplot_quote((t / "edges.dat").string()) << " using 1:2:3 with lines lc palette lw " << (boundary_only ? 2 : 1);
    if (!sol.contact.empty())
      script << ", " << gnuplot_quote((t / "contact.dat").string()) << " using 1:2 with points pt 7 ps 0.5 lc rgb 'black'";
    script << "\nunset output\n";
  }
  write_plain(t / "plots.gp", [&](std::ostream& os) { os << script.str(); });
  const std::string failure = run_gnuplot(gnuplot, t / "plots.gp", t / "gnuplot.log");
  auto finish = [&](bool wanted, const std::string& name) {
    if (!wanted) return;
    const fs::path made = t / name;
    if (!failure.empty() && !is_png(made)) {
      report.skipped.push_back(name + ": " + failure);
    } else if (!is_png(made)) {
      report.skipped.push_back(name + ": gnuplot made no PNG");
    } else {
      move_into_place(made, dir / name);
      report.written.push_back(dir / name);
    }
  };
  finish(want_unu, "u_nu.png");
  finish(want_deformed, "deformed.png");
}

}  // namespace

std::vector<std::array<int, 2>> contact_lines(const Mesh& mesh, const ContactSolution& sol) {
  std::vector<char> on(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (const auto& n : sol.contact) on[static_cast<std::size_t>(n.vertex)] = 1;
  std::vector<std::array<int, 2>> lines;
  if (sol.contact.empty()) return lines;
  for (int e : mesh.boundary_edges()) {
    const auto& edge = mesh.edge(e);
    if (on[static_cast<std::size_t>(edge.v0)] && on[static_cast<std::size_t>(edge.v1)]) lines.push_back({edge.v0, edge.v1});
  }
  return lines;
}

nlohmann::json result_json(const Mesh& mesh, const ContactSolution& s, const RunInfo& info) {
  using nlohmann::json;
  json j;
  j["schema"] = "hemivem-result/5";
  j["version"] = info.version;
  j["scene"] = {{"name", info.scene_name}, {"toml", info.scene_toml}};
  j["backends"] = {{"linear", info.linear}, {"minimizer", info.minimizer}};
  j["processes"] = info.processes;
  j["files"] = info.files;
  j["warnings"] = info.warnings;
  j["options"] = info.options;
  j["status"] = to_string(s.minimizer.status);
  j["converged"] = s.converged();
  j["message"] = s.minimizer.message;
  j["certificate"] = certificate_json(s.minimizer.certificate);
  j["uniqueness_margin"] = number(s.uniqueness_margin);
  j["may_be_nonunique"] = s.minimizer.may_be_nonunique;
  j["potential_energy"] = number(s.energy);
  j["iterations"] = s.minimizer.iterations;
  j["evaluations"] = {{"function", s.minimizer.function_evaluations},
                      {"subgradient", s.minimizer.subgradient_evaluations}};
  j["stages"] = s.stages;
  json t = json::object();
  for (const auto& [k, v] : s.timings) t[k] = number(v);
  t["mesh"] = number(info.mesh_seconds);
  for (const char* stage : {"assembly", "condensation", "minimize", "back_substitution"}) t[stage] = timing(s, stage);
  t["total"] = number(info.mesh_seconds + timing(s, "total"));
  j["timings"] = t;
  j["mesh"] = {{"description", info.mesh},
               {"vertices", mesh.num_vertices()},
               {"elements", mesh.num_elements()},
               {"dofs", info.dofs >= 0 ? info.dofs : 2 * mesh.num_vertices()},
               {"h", mesh.h()}};
  json contact = json::array();
  for (const auto& n : s.contact)
    contact.push_back({{"vertex", n.vertex},
                       {"x", n.x.x()},
                       {"y", n.x.y()},
                       {"u_nu", number(n.u_nu)},
                       {"law_force", number(n.law_force)},
                       {"reaction", number(n.reaction)},
                       {"pressure", number(n.pressure())},
                       {"gap", number(n.gap)},
                       {"normal", {number(n.normal.x()), number(n.normal.y())}},
                       {"state", n.state}});
  j["contact"] = std::move(contact);
  const Vec2 force = s.contact_force();
  j["contact_force"] = {number(force.x()), number(force.y())};
  const ContactZone zone = contact_zone(s);
  j["contact_zone"] = zone.nodes == 0 ? json(nullptr)
                                      : json{{"nodes", zone.nodes},
                                             {"length", number(zone.length)},
                                             {"x", {number(zone.lower.x()), number(zone.upper.x())}},
                                             {"y", {number(zone.lower.y()), number(zone.upper.y())}}};
  return j;
}

const std::vector<std::string>& all_outputs() {
  static const std::vector<std::string> names{"result.json",  "contact.csv", "displacement.csv", "history.csv",
                                              "solution.vtu", "scene.toml",  "u_nu.png",         "deformed.png"};
  return names;
}

void check_output_folder(const fs::path& dir) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st)) throw InputError("the output folder is a file, not a folder", dir.string());
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw InputError("cannot write into the output folder: " + std::string(std::strerror(errno)), dir.string());
    return;
  }
  // the folder will be made: its nearest existing ancestor must be a writable folder
  fs::path p = fs::absolute(dir, ec).parent_path();
  while (!p.empty() && !fs::exists(fs::status(p, ec))) {
    if (p == p.root_path()) break;
    p = p.parent_path();
  }
  if (!fs::is_directory(fs::status(p, ec)))
    throw InputError("cannot make the output folder: " + p.string() + " is not a folder", dir.string());
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw InputError("cannot make the output folder: cannot write into " + p.string() + ": " + std::strerror(errno),
                     dir.string());
}

OutputReport write_outputs(const fs::path& dir, const Mesh& mesh, const MaterialTable& materials,
                           const ContactSolution& solution, const RunInfo& info, const std::vector<std::string>& wanted) {
  const auto& known = all_outputs();
  for (const auto& w : wanted)
    if (std::find(known.begin(), known.end(), w) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError("unknown output '" + w + "' (known: " + list + ")");
    }
  if (solution.u.size() != 2 * mesh.num_vertices())
    throw InputError("the solution has " + std::to_string(solution.u.size()) + " values for " +
                     std::to_string(mesh.num_vertices()) + " vertices");
  auto want = [&](const std::string& name) { return std::find(wanted.begin(), wanted.end(), name) != wanted.end(); };

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError("cannot create the output folder" + (ec ? ": " + ec.message() : std::string()), dir.string());

  OutputReport report;
  auto write = [&](const std::string& name, const std::function<void(std::ostream&)>& body) {
    if (!want(name)) return;
    write_atomically(dir / name, body);
    report.written.push_back(dir / name);
  };
  RunInfo listed = info;  // result.json lists the run's files, in the order they are written
  listed.files.clear();
  for (const auto& k : known)
    if (want(k)) listed.files.push_back(k);
  write("result.json", [&](std::ostream& os) { os << result_json(mesh, solution, listed).dump(2) << '\n'; });
  write("contact.csv", [&](std::ostream& os) { write_contact_csv(os, solution); });
  write("displacement.csv", [&](std::ostream& os) { write_displacement_csv(os, mesh, solution.u); });
  write("history.csv", [&](std::ostream& os) { write_history_csv(os, solution); });
  write("solution.vtu", [&](std::ostream& os) { write_vtu(os, mesh, materials, solution); });
  write("scene.toml", [&](std::ostream& os) { os << info.scene_toml; });
  if (want("u_nu.png") || want("deformed.png")) {
    try {
      make_plots(dir, mesh, solution, want("u_nu.png"), want("deformed.png"), report);
    } catch (const std::exception& e) {
      // a plot is never worth failing the run for; a half-written one is never left behind
      // (each file is moved into place atomically)
      const std::string reason = e.what();
      for (const char* name : {"u_nu.png", "deformed.png"}) {
        const bool done = std::find(report.written.begin(), report.written.end(), dir / name) != report.written.end();
        const bool listed = std::any_of(report.skipped.begin(), report.skipped.end(), [&](const std::string& s) {
          return s.rfind(std::string(name) + ":", 0) == 0;
        });
        if (want(name) && !done && !listed) report.skipped.push_back(std::string(name) + ": " + reason);
      }
    }
  }
  // A plot that could not be made is not in the folder: result.json says so.
  if (want("result.json") && report.written.size() != listed.files.size()) {
    listed.files.clear();
    for (const auto& f : report.written) listed.files.push_back(f.filename().string());
    write_atomically(dir / "result.json", [&](std::ostream& os) { os << result_json(mesh, solution, listed).dump(2) << '\n'; });
  }
  // The folder holds exactly this run's outputs: an earlier run's file of a name this run
  // did not write goes (never anything else).
  for (const auto& k : known) {
    if (std::find(report.written.begin(), report.written.end(), dir / k) != report.written.end()) continue;
    std::error_code rm;
    if (fs::is_regular_file(fs::symlink_status(dir / k, rm)) && fs::remove(dir / k, rm)) report.removed.push_back(k);
  }
  return report;
}

}  // namespace hemivem::cli
