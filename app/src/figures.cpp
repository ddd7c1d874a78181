// The figures of a solve drawn with gnuplot (figures.hpp): the drawing of a set of figures,
// the house style, and the figures of plane and solid bodies.
#include <hemivem/app/figures.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <system_error>

#include <sys/wait.h>
#include <unistd.h>

#include <hemivem/support/atomic_file.hpp>
#include <hemivem/error.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/app/text_writer.hpp>

#include "figure_style.hpp"

namespace hemivem::app {

namespace fs = std::filesystem;
using detail::kViridis;
using detail::num;
using detail::solve_title;

namespace {

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

/// A single-quoted string for the shell.
std::string shell_quote(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return r + "'";
}

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
std::vector<std::vector<ContactPoint>> contact_chains(const Mesh& mesh, const detail::PlaneEdges& edges,
                                                     const ContactSolution& sol) {
  std::map<int, const ContactNode*> by_vertex;
  for (const auto& n : sol.contact) by_vertex[n.vertex] = &n;
  std::map<int, std::vector<int>> next;
  for (const auto& [v0, v1] : detail::contact_lines(mesh.num_vertices(), edges, sol)) {
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

/// A number for a label (6 significant digits).
std::string label_number(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

/// The polygon `poly` clipped to the half-plane n . (p - a) <= 0 (Sutherland-Hodgman).
std::vector<Vec2> clip_half_plane(const std::vector<Vec2>& poly, const Vec2& a, const Vec2& n) {
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    const double dp = n.dot(p - a), dq = n.dot(q - a);
    if (dp <= 0.0) out.push_back(p);
    if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) out.push_back(p + dp / (dp - dq) * (q - p));
  }
  return out;
}

/// The polygon `poly` clipped to the rectangle `frame`.
std::vector<Vec2> clip_to_frame(std::vector<Vec2> poly, const Rectangle& frame) {
  poly = clip_half_plane(poly, Vec2(frame.x0, 0.0), Vec2(-1.0, 0.0));
  poly = clip_half_plane(poly, Vec2(frame.x1, 0.0), Vec2(1.0, 0.0));
  poly = clip_half_plane(poly, Vec2(0.0, frame.y0), Vec2(0.0, -1.0));
  return clip_half_plane(poly, Vec2(0.0, frame.y1), Vec2(0.0, 1.0));
}

/// The obstacle's surface as a polyline long enough to cross `frame` (a plane's line, the
/// circle, the polyline itself), and the part of the obstacle inside `frame` as a polygon.
struct ObstacleDrawing {
  std::vector<Vec2> surface;
  std::vector<Vec2> region;
};
ObstacleDrawing draw_obstacle(const Obstacle& o, const Rectangle& frame) {
  const Vec2 centre(0.5 * (frame.x0 + frame.x1), 0.5 * (frame.y0 + frame.y1));
  ObstacleDrawing d;
  std::vector<Vec2> outline;  // the obstacle, or a polygon that holds all of it inside the frame
  switch (o.shape) {
    case Obstacle::Shape::plane: {
      const Vec2 n = o.normal.normalized(), t(-n.y(), n.x());
      const double far = 2.0 * std::hypot(frame.width(), frame.height()) + (o.point - centre).norm();
      d.surface = {o.point - far * t, o.point + far * t};
      outline = {o.point - far * t, o.point + far * t, o.point + far * t - far * n, o.point - far * t - far * n};
      break;
    }
    case Obstacle::Shape::circle:
      for (int k = 0; k <= 720; ++k) {
        const double a = 2.0 * std::numbers::pi * k / 720.0;
        d.surface.push_back(o.center + o.radius * Vec2(std::cos(a), std::sin(a)));
      }
      outline.assign(d.surface.begin(), d.surface.end() - 1);
      break;
    case Obstacle::Shape::polyline: {
      // the obstacle is on the right of the walk: close it far on that side
      d.surface = o.points;
      const double far = 2.0 * std::hypot(frame.width(), frame.height());
      auto right = [](const Vec2& a, const Vec2& b) {
        const Vec2 t = (b - a).normalized();
        return Vec2(t.y(), -t.x());
      };
      outline = o.points;
      outline.push_back(o.points.back() + far * right(o.points[o.points.size() - 2], o.points.back()));
      outline.push_back(o.points.front() + far * right(o.points[0], o.points[1]));
      break;
    }
  }
  d.region = clip_to_frame(outline, frame);
  return d;
}

/// The most edges deformed.png draws one by one (a 1000 x 700 picture).
constexpr std::size_t kMaxDrawnEdges = 100000;

/// The values u_nu.png's axis shows: u_nu's range, widened by the law's breakpoints near it
/// and by the gap where it is near it; a gap farther away is clipped (gap_clipped, with its
/// finite range gap_lo .. gap_hi) so that u_nu never becomes a flat line.
struct ValueRange {
  double lo = 0.0, hi = 0.0;
  std::vector<double> breakpoints;  ///< the law's breakpoints shown, ascending
  bool gap_clipped = false;
  double gap_lo = 0.0, gap_hi = 0.0;
};
ValueRange u_nu_range(const ContactSolution& sol, const RunInfo& info) {
  ValueRange r;
  r.lo = r.hi = sol.contact.front().u_nu;
  for (const auto& n : sol.contact) r.lo = std::min(r.lo, n.u_nu), r.hi = std::max(r.hi, n.u_nu);
  if (!(r.hi > r.lo)) {  // a constant u_nu: a range around it
    const double half = r.hi != 0.0 ? 0.1 * std::abs(r.hi) : 0.5;
    r.lo -= half, r.hi += half;
  }
  const double span = r.hi - r.lo, lo = r.lo, hi = r.hi;
  auto near = [&](double v) { return v >= lo - span && v <= hi + span; };
  for (double b : info.law_breakpoints)
    if (near(b)) r.breakpoints.push_back(b);
  std::sort(r.breakpoints.begin(), r.breakpoints.end());
  bool any_gap = false;
  for (const auto& n : sol.contact) {
    if (!info.gap_bound || !std::isfinite(n.gap)) continue;
    r.gap_lo = any_gap ? std::min(r.gap_lo, n.gap) : n.gap;
    r.gap_hi = any_gap ? std::max(r.gap_hi, n.gap) : n.gap;
    any_gap = true;
    if (near(n.gap)) r.lo = std::min(r.lo, n.gap), r.hi = std::max(r.hi, n.gap);
    else r.gap_clipped = true;
  }
  for (double b : r.breakpoints) r.lo = std::min(r.lo, b), r.hi = std::max(r.hi, b);
  return r;
}

/// A label of u_nu.png naming one breakpoint, or several that lie too close to be told apart.
struct BreakpointLabel {
  double at = 0.0;
  std::string text;
};
/// The labels of the ascending `breakpoints` on an axis from lo to hi: a breakpoint closer
/// than 5% of the axis above the last label's is named in that label, so that labels never
/// print over each other.
std::vector<BreakpointLabel> breakpoint_labels(const std::vector<double>& breakpoints, double lo, double hi) {
  std::vector<BreakpointLabel> labels;
  std::vector<std::size_t> count;
  for (double b : breakpoints) {
    if (!labels.empty() && b - labels.back().at < 0.05 * (hi - lo)) {
      labels.back().text += ", " + label_number(b);
      ++count.back();
      continue;
    }
    labels.push_back({b, label_number(b)});
    count.push_back(1);
  }
  for (std::size_t i = 0; i < labels.size(); ++i)
    labels[i].text = (count[i] > 1 ? "law breakpoints " : "law breakpoint ") + labels[i].text;
  return labels;
}

}  // namespace

namespace detail {

std::string num(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

/// `text` with every word that is a file path (a word with a '/' that starts with '/', '.' or
/// '~' or ends in a file name with an extension) cut to its file name: a title names a mesh
/// file, not the folders it was found in.
std::string without_folders(const std::string& text) {
  std::string r, word;
  auto flush = [&] {
    const auto slash = word.find_last_of('/');
    const bool rooted = !word.empty() && (word[0] == '/' || word[0] == '.' || word[0] == '~');
    const bool path = slash != std::string::npos && slash + 1 < word.size() &&
                      (rooted || word.find('.', slash) != std::string::npos);
    r += path ? word.substr(slash + 1) : word;
    word.clear();
  };
  for (char c : text) {
    if (c == ' ' || c == ',' || c == '(' || c == ')') {
      flush();
      r += c;
    } else {
      word += c;
    }
  }
  flush();
  return r;
}

std::string cut_title(std::string text) {
  // at a character boundary of UTF-8: gnuplot takes minutes over megabytes
  constexpr std::size_t kMaxTitle = 160;
  if (text.size() <= kMaxTitle) return text;
  std::size_t cut = kMaxTitle;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return text.substr(0, cut) + "...";
}

/// The title of a solve's figure as a gnuplot string: what it shows on the first line, the
/// scene and the mesh on the second (a long scene name would not fit on one).
std::string double_quoted_escape(const std::string& t) {
  std::string r;
  for (char c : t) {
    if (c == '"' || c == '\\') r += std::string("\\") + c;
    else if (c == '\n') r += "\\n";  // a line break in the figure, not in the script
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) r += ' ';
    else r += c;
  }
  return r;
}

std::string solve_title(const std::string& what, const RunInfo& info) {
  const auto escaped = double_quoted_escape;
  std::string second = cut_title(without_folders(info.scene_name));
  if (!info.mesh.empty()) second += (second.empty() ? "" : ", ") + without_folders(info.mesh);
  return "\"" + escaped(what) + (second.empty() ? "" : "\\n" + escaped(second)) + "\"";
}

}  // namespace detail

std::string gnuplot_quote(const std::string& s) {
  std::string r = "'";
  for (char c : s) {
    if (c == '\'') r += "''";
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) r += ' ';  // a newline would end the command
    else r += c;
  }
  return r + "'";
}

std::string tick_format(double lo, double hi) {
  const double mag = std::max(std::abs(lo), std::abs(hi));
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(mag > 0.0)) return "%g";
  const double span = std::abs(hi - lo) > 0.0 ? std::abs(hi - lo) : 0.1 * mag;
  // the exponents of the largest number (a tenth of the span beyond the range: gnuplot may
  // extend an axis to its next tick) and of the smallest step, 1e-9 above round-off
  const int top = static_cast<int>(std::floor(std::log10(mag + 0.1 * span) + 1e-9));
  const int step = static_cast<int>(std::floor(std::log10(span / 20.0) + 1e-9));
  int digits = std::max(3, top - step + 1);
  if (top >= 0 && top < 7) digits = std::max(digits, top + 1);  // 12500, not 1.25e+04
  return "%." + std::to_string(std::min(digits, 15)) + "g";
}

std::string axis_format(const std::string& axis, double lo, double hi) {
  return "set format " + axis + " \"" + tick_format(lo, hi) + "\"\n";
}

double tick_step(double lo, double hi, int intervals) {
  const double span = std::abs(hi - lo);
  if (!std::isfinite(span) || !(span > 0.0)) return 0.0;
  intervals = std::max(intervals, 1);
  double step = std::pow(10.0, std::floor(std::log10(span / intervals)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (span / (m * step) <= intervals * (1.0 + 1e-9)) return m * step;
  return 10.0 * step;
}

double mesh_line_width(long long elements) {
  if (elements <= 100) return 1.0;
  return std::max(0.05, 10.0 / std::sqrt(static_cast<double>(elements)));
}

bool is_png(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in.gcount() == 8 && std::string(sig, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}

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

const std::vector<std::string>& figure_formats() {
  static const std::vector<std::string> formats{"png", "pdf", "svg"};
  return formats;
}

std::vector<std::string> figure_files(const Figure& figure, const std::vector<std::string>& formats) {
  const std::string stem = fs::path(figure.png).replace_extension().string();
  std::vector<std::string> files;
  for (const auto& format : formats) files.push_back(format == "png" ? figure.png : stem + "." + format);
  return files;
}

bool is_figure_file(const fs::path& p, const std::string& format) {
  if (format == "png") return is_png(p);
  std::ifstream in(p, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (format == "pdf") return head.rfind("%PDF-", 0) == 0;
  if (format == "svg") return head.find("<svg") != std::string::npos;
  return false;
}

namespace {

/// The gnuplot lines that make `format` the terminal of a picture of width x height points.
std::string terminal_lines(const std::string& format, int width, int height) {
  const std::string size = std::to_string(width) + "," + std::to_string(height);
  std::ostringstream t;
  // a terminal this gnuplot lacks draws nothing (the terminal unknown): the figure is then
  // reported as not drawn, and the other figures are drawn
  if (format == "pdf") {  // a hundred points to the inch: the PNG's proportions, its fonts as large
    t << "if (strstrt(GPVAL_TERMINALS, ' pdfcairo ') > 0) { set terminal pdfcairo size " << num(width / 100.0) << "in,"
      << num(height / 100.0) << "in enhanced font 'sans,11' } else { set terminal unknown }\n";
  } else if (format == "svg") {
    t << "if (strstrt(GPVAL_TERMINALS, ' svg ') > 0) { set terminal svg size "
      << size << " enhanced font 'sans,11' background '#ffffff' } else { set terminal unknown }\n";
  } else {  // pngcairo when built in, else the gd-based png terminal
    t << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) { set terminal pngcairo size " << size
      << " enhanced font 'sans,11' } else { set terminal png size " << size << " }\n";
  }
  return t.str();
}

/// The terminal gnuplot needs for `format`.
std::string terminal_of(const std::string& format) {
  return format == "pdf" ? "pdfcairo" : format == "svg" ? "svg" : "png";
}

}  // namespace

std::vector<std::string> draw_figures(const fs::path& dir, const std::vector<Figure>& figures,
                                      const std::vector<std::string>& formats) {
  std::vector<std::string> reasons(figures.size());
  if (figures.empty()) return reasons;
  for (const auto& format : formats)
    if (std::find(figure_formats().begin(), figure_formats().end(), format) == figure_formats().end())
      throw InputError("unknown figure format '" + format + "' (expected any of: png, pdf, svg)");
  const fs::path gnuplot = find_on_path("gnuplot");
  if (gnuplot.empty()) {
    std::fill(reasons.begin(), reasons.end(), "gnuplot not found on PATH");
    return reasons;
  }
  TempDir tmp;
  const fs::path& t = tmp.path();
  std::ostringstream script;
  for (const Figure& f : figures) {
    for (const auto& d : f.data) write_plain(t / d.name, d.write);
    const std::vector<std::string> files = figure_files(f, formats);
    for (std::size_t k = 0; k < formats.size(); ++k) {
      script << terminal_lines(formats[k], f.width, f.height) << "set output " << gnuplot_quote(files[k]) << "\n"
             << f.script << "\nunset output\nreset\n";
    }
  }
  write_plain(t / "figures.gp", [&](std::ostream& os) { os << script.str(); });
  const fs::path log = t / "gnuplot.log";
  const std::string command = "cd " + shell_quote(t.string()) + " && " + shell_quote(gnuplot.string()) +
                              " figures.gp >" + shell_quote(log.string()) + " 2>&1";
  const int rc = std::system(command.c_str());
  std::string failure;
  if (rc != 0) {
    std::ifstream in(log);
    std::string first_line;
    std::getline(in, first_line);
    const int status = rc > 0 && WIFEXITED(rc) ? WEXITSTATUS(rc) : rc;  // std::system's wait status
    failure = "gnuplot failed (exit status " + std::to_string(status) + ")" + (first_line.empty() ? "" : ": " + first_line);
  }
  for (std::size_t i = 0; i < figures.size(); ++i) {
    // a figure is moved into place in every format or in none
    const std::vector<std::string> files = figure_files(figures[i], formats);
    for (std::size_t k = 0; k < formats.size() && reasons[i].empty(); ++k)
      if (!is_figure_file(t / files[k], formats[k])) {
        std::string upper = formats[k];
        for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        reasons[i] = !failure.empty() ? failure
                     : formats[k] == "png" ? "gnuplot made no PNG"
                                           : "gnuplot made no " + upper + " (it needs gnuplot's " +
                                                 terminal_of(formats[k]) + " terminal)";
      }
    if (!reasons[i].empty()) continue;
    for (const auto& name : files)
      write_atomically(dir / name, [&](std::ostream& os) {
        std::ifstream in(t / name, std::ios::binary);
        if (!in) throw InputError("cannot read", (t / name).string());
        os << in.rdbuf();
      });
  }
  return reasons;
}

namespace {

/// The formats of u_nu.png's x axis (x or the arc length) and pressure axis: tick labels that
/// differ at any scale.
std::string u_nu_formats(const std::vector<std::vector<ContactPoint>>& chains, bool along_x) {
  double x_lo = 0.0, x_hi = 0.0, p_lo = 0.0, p_hi = 0.0;
  bool first = true;
  for (const auto& chain : chains)
    for (const auto& p : chain) {
      const double at = along_x ? p.node->x.x() : p.s, pressure = p.node->pressure();
      x_lo = first ? at : std::min(x_lo, at), x_hi = first ? at : std::max(x_hi, at);
      if (std::isfinite(pressure)) p_lo = std::min(p_lo, pressure), p_hi = std::max(p_hi, pressure);
      first = false;
    }
  return axis_format("x", x_lo, x_hi) + axis_format("y2", p_lo, p_hi);
}

/// u_nu.png's second panel with friction: u_tau along the column `x` of u_nu.dat, its stick and
/// slip nodes marked, and the friction traction on the second axis.
std::string friction_panel(const ContactSolution& sol, const char* x) {
  double traction = 0.0, t_lo = 0.0, t_hi = 0.0;
  for (const auto& n : sol.contact) {
    if (std::isfinite(n.friction_force / n.weight)) traction = std::max(traction, std::abs(n.friction_force / n.weight));
    if (std::isfinite(n.u_tau)) t_lo = std::min(t_lo, n.u_tau), t_hi = std::max(t_hi, n.u_tau);
  }
  std::ostringstream s;
  s << "unset arrow\nunset label\nunset yrange\n" << axis_format("y", t_lo, t_hi)
    << axis_format("y2", -1.1 * traction, 1.1 * traction);
  if (traction > 0.0) s << "set y2range [" << num(-1.1 * traction) << ":" << num(1.1 * traction) << "]\n";
  s << "set title " << gnuplot_quote("tangential displacement and friction on the contact boundary: stick and slip zones")
    << " noenhanced\n"
    << "set ylabel 'tangential displacement u_{/Symbol t} (scene units)'\n"
    << "set y2label 'friction traction (force per unit length, scene units)'\n"
    << "plot 'u_nu.dat' using " << x << ":7 with lines lw 2 lc rgb '#1f77b4' title 'u_{/Symbol t}'"
    << ", '' using " << x << ":($9 > 0 ? $7 : NaN) with points pt 5 ps 0.9 lc rgb '#2ca02c' title 'stick'"
    << ", '' using " << x << ":($9 > 0 ? NaN : $7) with points pt 9 ps 0.9 lc rgb '#ff7f0e' title 'slip'"
    << ", '' using " << x << ":8 axes x1y2 with linespoints pt 6 ps 0.5 lw 1.5 lc rgb '#d62728' title 'friction traction'";
  return s.str();
}

}  // namespace

namespace {

Figure u_nu_figure_of(const Mesh& mesh, const detail::PlaneEdges& edges, const ContactSolution& sol, const RunInfo& info) {
  const auto chains = contact_chains(mesh, edges, sol);
  // against x when Gamma_3 is one horizontal line, else against its arc length
  const Rectangle box = mesh.bounding_box();
  double y_min = sol.contact.front().x.y(), y_max = y_min;
  for (const auto& n : sol.contact) y_min = std::min(y_min, n.x.y()), y_max = std::max(y_max, n.x.y());
  const bool along_x = chains.size() == 1 && y_max - y_min <= 1e-12 * std::max(box.width(), box.height());
  const ValueRange range = u_nu_range(sol, info);
  const double lo = range.lo, hi = range.hi, margin = 0.06 * (hi - lo);
  const std::vector<BreakpointLabel> labels = breakpoint_labels(range.breakpoints, lo - margin, hi + margin);
  const std::vector<double>& breakpoints = range.breakpoints;

  Figure f;
  f.png = "u_nu.png";
  const bool tangential = has_tangential(sol);
  f.data.push_back({"u_nu.dat", [chains](std::ostream& os) {
                      os << std::setprecision(17)
                         << "# s x y u_nu pressure gap u_tau friction_traction stick\n";
                      for (const auto& chain : chains) {
                        for (const auto& p : chain)
                          os << p.s << ' ' << p.node->x.x() << ' ' << p.node->x.y() << ' ' << p.node->u_nu << ' '
                             << p.node->pressure() << ' ' << p.node->gap << ' ' << p.node->u_tau << ' '
                             << p.node->friction_force / p.node->weight << ' '
                             << (p.node->friction_state == FrictionState::stick ? 1 : 0) << '\n';
                        os << "\n\n";  // a new data block per chain
                      }
                    }});
  std::ostringstream s;
  if (tangential) {  // a second panel below: u_tau with the stick and slip zones, the friction traction
    f.height = 1200;
    s << "set multiplot layout 2,1\n";
  }
  s << "set title " << solve_title("normal displacement and contact pressure on the contact boundary", info)
    << " noenhanced\n"
    << "set xlabel "
    << (along_x ? "'x (scene units)'" : "'arc length s along the contact boundary {/Symbol G}_3 (scene units)'") << "\n"
    << "set ylabel 'normal displacement u_{/Symbol n} (scene units)'\n"
    << "set y2label 'contact pressure (force per unit length, scene units; compression > 0)'\n"
    << "set ytics nomirror\nset y2tics\nset grid\nset key outside top center horizontal\nset clip two\n"
    << "set yrange [" << num(lo - margin) << ":" << num(hi + margin) << "]\n";
  s << u_nu_formats(chains, along_x) << axis_format("y", lo - margin, hi + margin);
  for (double b : breakpoints)
    s << "set arrow from graph 0, first " << num(b) << " to graph 1, first " << num(b)
      << " nohead dt 3 lw 1.5 lc rgb '#2ca02c'\n";
  if (!labels.empty()) s << "set style textbox opaque fc rgb '#50ffffff' noborder\n";
  for (const auto& l : labels)
    s << "set label " << gnuplot_quote(l.text) << " at graph 0.01, first " << num(l.at)
      << " offset 0,0.6 boxed front tc rgb '#2ca02c' font ',9'\n";
  const char* x = along_x ? "2" : "1";
  s << "plot 'u_nu.dat' using " << x << ":4 with linespoints pt 7 ps 0.6 lw 2 lc rgb '#1f77b4' title 'u_{/Symbol n}'";
  if (info.gap_bound) {
    auto short_number = [](double v) {
      std::ostringstream o;
      o << std::setprecision(3) << v;
      return o.str();
    };
    const std::string clipped =
        range.gap_clipped ? "; clipped, from " + short_number(range.gap_lo) + " to " + short_number(range.gap_hi) : "";
    s << ", '' using " << x << ":6 with lines dt 2 lw 1.5 lc rgb '#555555' title "
      << gnuplot_quote("gap g (u_{/Symbol n} <= g" + clipped + ")");
  }
  s << ", '' using " << x << ":5 axes x1y2 with linespoints pt 6 ps 0.5 lw 1.5 lc rgb '#d62728' title 'contact pressure'";
  if (!breakpoints.empty()) s << ", NaN with lines dt 3 lw 1.5 lc rgb '#2ca02c' title 'contact law breakpoints'";
  if (tangential) s << "\n" << friction_panel(sol, x) << "\nunset multiplot";
  f.script = s.str();
  return f;
}

/// The frame of deformed.png: the undeformed and the deformed body (displacement x scale)
/// with a margin of 5% of their size on each side.
Rectangle body_frame(const Mesh& mesh, const ContactSolution& sol, double scale) {
  Rectangle f{mesh.vertex(0).x(), mesh.vertex(0).x(), mesh.vertex(0).y(), mesh.vertex(0).y()};
  auto take = [&f](const Vec2& p) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return;
    f.x0 = std::min(f.x0, p.x()), f.x1 = std::max(f.x1, p.x());
    f.y0 = std::min(f.y0, p.y()), f.y1 = std::max(f.y1, p.y());
  };
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    take(mesh.vertex(v));
    take(mesh.vertex(v) + scale * Vec2(sol.u(2 * v), sol.u(2 * v + 1)));
  }
  const double margin = 0.05 * std::max({f.width(), f.height(), 1e-300});
  return {f.x0 - margin, f.x1 + margin, f.y0 - margin, f.y1 + margin};
}

/// The magnification of deformed.png: the largest displacement `umax` shows as a tenth of the
/// body's size `size` (never shrunk).
double magnification(double size, double umax) {
  return umax > 0.0 && std::isfinite(umax) ? std::max(1.0, 0.1 * size / umax) : 1.0;
}

/// The data of a polyline or polygon: one "x y" row per point.
PlotData points_data(const std::string& name, const std::string& header, std::vector<Vec2> points) {
  return {name, [header, points = std::move(points)](std::ostream& os) {
            os << std::setprecision(17) << "# " << header << '\n';
            for (const Vec2& p : points) os << p.x() << ' ' << p.y() << '\n';
          }};
}

/// deformed.png's data: the deformed edges coloured by |u|, the undeformed outline, the
/// contact nodes (displacement x scale).
void add_body_data(Figure& f, const Mesh& mesh, const detail::PlaneEdges& edges, const ContactSolution& sol, double scale,
                   bool boundary_only) {
  f.data.push_back({"edges.dat", [&mesh, edges, &sol, scale, boundary_only](std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# x y |u| (deformed edges, one block each)\n";
                      const detail::PlaneEdges::Visit put = [&](int v0, int v1) {
                        for (int v : {v0, v1}) {
                          const Vec2 p = mesh.vertex(v) + scale * Vec2(sol.u(2 * v), sol.u(2 * v + 1));
                          os << p.x() << ' ' << p.y() << ' ' << std::hypot(sol.u(2 * v), sol.u(2 * v + 1)) << '\n';
                        }
                        os << '\n';
                      };
                      (boundary_only ? edges.boundary : edges.every)(put);
                    }});
  f.data.push_back({"outline.dat", [&mesh, edges](std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# x y (undeformed boundary edges, one block each)\n";
                      edges.boundary([&](int v0, int v1) {
                        for (int v : {v0, v1}) os << mesh.vertex(v).x() << ' ' << mesh.vertex(v).y() << '\n';
                        os << '\n';
                      });
                    }});
  if (sol.contact.empty()) return;
  std::vector<Vec2> nodes;
  for (const auto& n : sol.contact)
    nodes.push_back(mesh.vertex(n.vertex) + scale * Vec2(sol.u(2 * n.vertex), sol.u(2 * n.vertex + 1)));
  f.data.push_back(points_data("contact.dat", "x y (deformed contact nodes)", std::move(nodes)));
}

/// foundation.dat: where u_nu = g, x_i + g_i nu_i moved by the displacement's magnification
/// (a node touching it is drawn on it); one block per chain of contact nodes.
PlotData foundation_data(const Mesh& mesh, const detail::PlaneEdges& edges, const ContactSolution& sol, double scale) {
  return {"foundation.dat", [chains = contact_chains(mesh, edges, sol), scale](std::ostream& os) {
            os << std::setprecision(17) << "# x y (where u_nu = g, magnified as the displacement)\n";
            for (const auto& chain : chains) {
              for (const auto& p : chain) {
                if (!std::isfinite(p.node->gap)) {  // a ray that misses the obstacle
                  os << '\n';
                  continue;
                }
                const Vec2 q = p.node->x + scale * p.node->gap * p.node->normal;
                os << q.x() << ' ' << q.y() << '\n';
              }
              os << "\n\n";
            }
          }};
}

Figure deformed_figure_of(const Mesh& mesh, const detail::PlaneEdges& edges, const ContactSolution& sol, const RunInfo& info) {
  const bool contact = !sol.contact.empty();
  const bool obstacle = contact && info.obstacle.has_value();
  // Magnify the displacement so that its largest value shows as 10% of the domain's size;
  // a rigid obstacle is drawn where it is, so the body with it at its true displacement.
  const Rectangle box = mesh.bounding_box();
  const double size = std::hypot(box.width(), box.height());
  double umax = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) umax = std::max(umax, std::hypot(sol.u(2 * v), sol.u(2 * v + 1)));
  const double scale = obstacle ? 1.0 : magnification(size, umax);
  // Edges finer than the picture's pixels only cost time: a mesh with more edges than
  // kMaxDrawnEdges is drawn by its boundary.
  const bool boundary_only = !draws_every_edge(edges.count);
  const bool foundation = contact && info.gap_bound && !obstacle;
  const Rectangle frame = body_frame(mesh, sol, scale);

  Figure f;
  f.png = "deformed.png";
  // a flat body gets a lower picture, so that the key and the labels stay near it
  f.height = static_cast<int>(std::clamp(170.0 + 720.0 * frame.height() / frame.width(), 350.0, 700.0));
  add_body_data(f, mesh, edges, sol, scale, boundary_only);
  if (foundation) f.data.push_back(foundation_data(mesh, edges, sol, scale));
  bool obstacle_seen = false;
  if (obstacle) {
    ObstacleDrawing d = draw_obstacle(*info.obstacle, frame);
    obstacle_seen = !d.region.empty();
    f.data.push_back(points_data("obstacle.dat", "x y (the rigid obstacle inside the frame)", std::move(d.region)));
    f.data.push_back(points_data("surface.dat", "x y (the obstacle's surface)", std::move(d.surface)));
  }
  std::ostringstream title;
  title << (boundary_only ? "deformed boundary" : "deformed mesh");
  if (obstacle) title << " at true scale with the rigid obstacle";
  else title << " (displacement x " << std::setprecision(3) << scale << ")";
  if (boundary_only) title << "; " << edges.count << " edges are finer than the picture";
  std::ostringstream s;
  s << "set title " << solve_title(title.str(), info) << " noenhanced\n"
    << "set size ratio -1\nset clip two\n"
    << "set xrange [" << num(frame.x0) << ":" << num(frame.x1) << "]\n"
    << "set yrange [" << num(frame.y0) << ":" << num(frame.y1) << "]\n"
    << axis_format("x", frame.x0, frame.x1) << axis_format("y", frame.y0, frame.y1) << axis_format("cb", 0.0, umax)
    << "set xlabel 'x (scene units)'\nset ylabel 'y (scene units)'\n"
    << "set key outside bottom center horizontal maxrows 1 samplen 2 height 1.5\n"
    << kViridis << "set cblabel '|u| (scene units)'\nplot ";
  if (obstacle)
    s << "'obstacle.dat' using 1:2 with filledcurves closed fs solid 0.3 noborder lc rgb '#808080' notitle, "
      << "'surface.dat' using 1:2 with lines lw 2.5 lc rgb 'black' title "
      << (obstacle_seen ? "'rigid obstacle'" : "'rigid obstacle (outside the frame)'") << ", ";
  s << "'outline.dat' using 1:2 with lines lw 1.5 dt 2 lc rgb '#444444' title 'undeformed', "
    << "'edges.dat' using 1:2:3 with lines lc palette lw " << (boundary_only ? 2 : 1) << " notitle";
  if (foundation)
    s << ", 'foundation.dat' using 1:2 with lines lw 2.5 lc rgb 'black' title 'foundation (u_{/Symbol n} = g)'";
  if (contact) s << ", 'contact.dat' using 1:2 with points pt 7 ps 0.5 lc rgb '#d62728' title 'contact nodes'";
  f.script = s.str();
  return f;
}

}  // namespace

bool draws_every_edge(std::size_t edges) { return edges <= kMaxDrawnEdges; }

Figure u_nu_figure(const Mesh& mesh, const ContactSolution& sol, const RunInfo& info) {
  return u_nu_figure_of(mesh, detail::plane_edges(mesh), sol, info);
}
Figure u_nu_figure(const Mesh& mesh, const WholeOfPieces& whole, const ContactSolution& sol, const RunInfo& info) {
  return u_nu_figure_of(mesh, detail::plane_edges(whole), sol, info);
}

Figure deformed_figure(const Mesh& mesh, const ContactSolution& sol, const RunInfo& info) {
  return deformed_figure_of(mesh, detail::plane_edges(mesh), sol, info);
}
Figure deformed_figure(const Mesh& mesh, const WholeOfPieces& whole, const ContactSolution& sol, const RunInfo& info) {
  return deformed_figure_of(mesh, detail::plane_edges(whole), sol, info);
}

namespace detail {

PlaneEdges plane_edges(const Mesh& mesh) {
  PlaneEdges e;
  e.count = mesh.edges().size();
  e.boundary = [&mesh](const PlaneEdges::Visit& visit) {
    for (const int i : mesh.boundary_edges()) visit(mesh.edge(i).v0, mesh.edge(i).v1);
  };
  e.every = [&mesh](const PlaneEdges::Visit& visit) {
    for (const MeshEdge& edge : mesh.edges()) visit(edge.v0, edge.v1);
  };
  return e;
}

PlaneEdges plane_edges(const WholeOfPieces& whole) {
  PlaneEdges e;
  e.count = static_cast<std::size_t>(whole.size.facets);
  e.boundary = [&whole](const PlaneEdges::Visit& visit) {
    for (const std::vector<int>& loop : whole.boundary) {
      if (loop.size() != 2) throw InternalError("a plane's boundary edge of " + std::to_string(loop.size()) + " vertices");
      visit(loop[0], loop[1]);
    }
  };
  e.every = [&whole](const PlaneEdges::Visit& visit) {
    if (whole.edges.size() != static_cast<std::size_t>(whole.size.facets))
      throw InternalError(std::to_string(whole.edges.size()) + " edges gathered of " + std::to_string(whole.size.facets));
    for (const auto& [v0, v1] : whole.edges) visit(v0, v1);
  };
  return e;
}

std::vector<std::array<int, 2>> contact_lines(int vertices, const PlaneEdges& edges, const ContactSolution& sol) {
  std::vector<std::array<int, 2>> lines;
  if (sol.contact.empty()) return lines;
  std::vector<char> on(static_cast<std::size_t>(vertices), 0);
  for (const auto& n : sol.contact) on[static_cast<std::size_t>(n.vertex)] = 1;
  edges.boundary([&](int v0, int v1) {
    if (on[static_cast<std::size_t>(v0)] && on[static_cast<std::size_t>(v1)]) lines.push_back({v0, v1});
  });
  return lines;
}

}  // namespace detail

namespace {

// The figures of a solid: polygons as pm3d patches, each quadrilateral one patch and any other
// polygon a fan of triangles from its centroid, coloured by a value at the vertices.

/// The most tick intervals of an axis of a solid's deformed.png (its longest axis has them).
constexpr int kMaxTicIntervals3D = 5;

/// The most boundary faces deformed.png draws (a 1000 x 800 picture): beyond, the faces are
/// finer than the picture's pixels and only cost time.
constexpr std::size_t kMaxDrawnFaces = 200000;

/// One polygon with a value at each corner, written as pm3d patches of "a b c value" rows: a
/// quadrilateral as one 2 x 2 patch, another polygon as triangles (centroid, z_i, z_{i+1}),
/// each a 2 x 2 patch with the centroid twice. Patches are separated by two blank lines.
void put_polygon(TextWriter& os, const std::vector<Vec3>& p, const std::vector<double>& value) {
  auto row = [&](const Vec3& x, double v) { os << x.x() << ' ' << x.y() << ' ' << x.z() << ' ' << v << '\n'; };
  if (p.size() == 4) {
    row(p[0], value[0]), row(p[1], value[1]);
    os << '\n';
    row(p[3], value[3]), row(p[2], value[2]);
    os << "\n\n";
    return;
  }
  Vec3 c = Vec3::Zero();
  double cv = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) c += p[i], cv += value[i];
  c /= static_cast<double>(p.size());
  cv /= static_cast<double>(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t j = (i + 1) % p.size();
    row(c, cv), row(p[i], value[i]);
    os << '\n';
    row(c, cv), row(p[j], value[j]);
    os << "\n\n";
  }
}

Vec3 displacement(const ContactSolution3D& sol, int v) { return sol.u.segment<3>(3 * static_cast<Eigen::Index>(v)); }

}  // namespace

Figure deformed_figure(const Mesh3D& mesh, const ContactSolution3D& sol, const RunInfo& info) {
  std::vector<std::vector<int>> faces;
  faces.reserve(mesh.boundary_faces().size());
  for (const int f : mesh.boundary_faces()) faces.push_back(mesh.face(f).vertices);
  return deformed_figure(mesh, std::move(faces), sol, info);
}

Figure deformed_figure(const Mesh3D& mesh, std::vector<std::vector<int>> faces, const ContactSolution3D& sol,
                       const RunInfo& info) {
  const Box box = mesh.bounding_box();
  const double size = std::sqrt(box.size(0) * box.size(0) + box.size(1) * box.size(1) + box.size(2) * box.size(2));
  double umax = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) umax = std::max(umax, displacement(sol, v).norm());
  const double scale = magnification(size, umax);
  const std::size_t count = faces.size();
  const bool all = count <= kMaxDrawnFaces;

  Figure f;
  f.png = "deformed.png";
  f.height = 800;
  f.data.push_back({"faces.dat", [&mesh, &sol, faces = std::move(faces), scale, all](std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# x y z |u| (deformed boundary faces as pm3d patches)\n";
                      std::vector<Vec3> p;
                      std::vector<double> value;
                      for (std::size_t k = 0; k < faces.size(); ++k) {
                        if (!all && k % ((faces.size() + kMaxDrawnFaces - 1) / kMaxDrawnFaces) != 0) continue;
                        p.clear();
                        value.clear();
                        for (int v : faces[k]) {
                          const Vec3 u = displacement(sol, v);
                          p.push_back(mesh.vertex(v) + scale * u);
                          value.push_back(u.norm());
                        }
                        put_polygon(os, p, value);
                      }
                    }});
  // the deformed body's extent per axis: each axis has ticks in proportion to its length, so
  // that the short axis of a flat body is not crowded with labels
  std::array<double, 3> lo{}, hi{};
  for (int c = 0; c < 3; ++c) lo[c] = hi[c] = mesh.vertex(0)(c);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 x = mesh.vertex(v) + scale * displacement(sol, v);
    for (int c = 0; c < 3; ++c)
      if (std::isfinite(x(c))) lo[c] = std::min(lo[c], x(c)), hi[c] = std::max(hi[c], x(c));
  }
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  std::ostringstream tics;
  for (int c = 0; c < 3; ++c) {
    const std::string axis(1, "xyz"[c]);
    const int intervals =
        longest > 0.0 ? static_cast<int>(std::clamp(std::round(kMaxTicIntervals3D * (hi[c] - lo[c]) / longest), 1.0,
                                                    static_cast<double>(kMaxTicIntervals3D)))
                      : kMaxTicIntervals3D;
    const double step = tick_step(lo[c], hi[c], intervals);
    if (step > 0.0)  // the body's own extent: gnuplot would widen it to the next ticks
      tics << "set " << axis << "range [" << num(lo[c]) << ":" << num(hi[c]) << "]\nset " << axis << "tics " << num(step)
           << "\n";
    tics << axis_format(axis, lo[c], hi[c]);
  }
  tics << axis_format("cb", 0.0, umax);
  std::ostringstream title;
  title << "deformed body (displacement x " << std::setprecision(3) << scale << "), coloured by |u|";
  if (!all) title << "; " << count << " boundary faces, one in " << (count + kMaxDrawnFaces - 1) / kMaxDrawnFaces << " drawn";
  std::ostringstream s;
  s << "set title " << solve_title(title.str(), info) << " noenhanced\n"
    << "set view 62, 32\nset view equal xyz\nset xyplane at " << num(box.z0 - 0.05 * size) << "\n"
    << "set xlabel 'x'\nset ylabel 'y'\nset zlabel 'z'\nset tics font ',9'\n" << tics.str()
    << "set pm3d depthorder border lc rgb '#303030' lw 0.4\nunset key\n"
    << kViridis << "set cblabel '|u| (scene units)'\n"
    << "splot 'faces.dat' using 1:2:3:4 with pm3d notitle";
  f.script = s.str();
  return f;
}

namespace {

// The stick/slip map over pressure.png: stuck nodes as dots, slipping ones as arrows of their
// tangential displacement in the picture's plane (axes a, b), the longest a twelfth of `extent`.
void add_stick_slip_map(Figure& f, std::ostringstream& s, const ContactSolution3D& sol, int a, int b, double extent) {
  double longest = 0.0;
  for (const auto& n : sol.contact)
    if (n.friction_state != FrictionState::none && n.friction_state != FrictionState::stick)
      longest = std::max(longest, std::hypot(n.u_tangential(a), n.u_tangential(b)));
  const double scale = longest > 0.0 ? extent / (12.0 * longest) : 0.0;
  f.data.push_back({"friction.dat", [nodes = sol.contact, a, b, scale](std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# a b 0 da db 0 (stuck nodes, then a blank line and the slipping ones)\n";
                      for (const bool stuck : {true, false}) {
                        for (const auto& n : nodes) {
                          if (n.friction_state == FrictionState::none || (n.friction_state == FrictionState::stick) != stuck)
                            continue;
                          os << n.x(a) << ' ' << n.x(b) << " 0 " << scale * n.u_tangential(a) << ' '
                             << scale * n.u_tangential(b) << " 0\n";
                        }
                        os << "\n\n";
                      }
                    }});
  s << ", \\\n  'friction.dat' index 0 using 1:2:3 with points pt 7 ps 0.6 lc rgb '#000000' title 'stick', \\\n"
    << "  'friction.dat' index 1 using 1:2:3:4:5:6 with vectors head filled size screen 0.008,20 lc rgb '#d62728' "
       "title 'slip (tangential displacement)'";
}

}  // namespace

Figure pressure_figure(const Mesh3D& mesh, const std::vector<int>& faces, const ContactSolution3D& sol,
                       const RunInfo& info) {
  std::vector<std::vector<int>> loops;
  loops.reserve(faces.size());
  for (const int f : faces) loops.push_back(mesh.face(f).vertices);
  return pressure_figure(mesh, std::move(loops), sol, info);
}

Figure pressure_figure(const Mesh3D& mesh, std::vector<std::vector<int>> faces, const ContactSolution3D& sol,
                       const RunInfo& info) {
  // the axis the contact faces are seen along: the largest component of their mean normal
  Vec3 mean = Vec3::Zero();
  for (const auto& n : sol.contact) mean += n.weight * n.normal;
  int along = 2;
  mean.cwiseAbs().maxCoeff(&along);
  const int a = along == 0 ? 1 : 0, b = along == 2 ? 1 : 2;
  const char* names = "xyz";
  std::vector<double> pressure(static_cast<std::size_t>(mesh.num_vertices()), 0.0);
  double lo = 0.0, hi = 0.0;
  for (const auto& n : sol.contact) {
    const double p = std::isfinite(n.pressure()) ? n.pressure() : 0.0;
    pressure[static_cast<std::size_t>(n.vertex)] = p;
    lo = std::min(lo, p), hi = std::max(hi, p);
  }
  double a_lo = 0.0, a_hi = 0.0, b_lo = 0.0, b_hi = 0.0;  // the extent of the map, for its height
  bool first = true;
  for (const auto& face : faces)
    for (int v : face) {
      const Vec3& x = mesh.vertex(v);
      a_lo = first ? x(a) : std::min(a_lo, x(a)), a_hi = first ? x(a) : std::max(a_hi, x(a));
      b_lo = first ? x(b) : std::min(b_lo, x(b)), b_hi = first ? x(b) : std::max(b_hi, x(b));
      first = false;
    }
  Figure f;
  f.png = "pressure.png";
  // a flat contact surface gets a lower picture, so that the colour bar stays near it
  const double aspect = a_hi > a_lo ? (b_hi - b_lo) / (a_hi - a_lo) : 1.0;
  f.height = static_cast<int>(std::clamp(200.0 + 700.0 * aspect, 400.0, 900.0));
  f.data.push_back({"pressure.dat", [&mesh, faces = std::move(faces), pressure, a, b](std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# a b 0 pressure (the contact faces seen along their normal, as pm3d patches)\n";
                      std::vector<Vec3> p;
                      std::vector<double> value;
                      for (const auto& face : faces) {
                        p.clear();
                        value.clear();
                        for (int v : face) {
                          const Vec3& x = mesh.vertex(v);
                          p.emplace_back(x(a), x(b), 0.0);
                          value.push_back(pressure[static_cast<std::size_t>(v)]);
                        }
                        put_polygon(os, p, value);
                      }
                    }});
  std::ostringstream s;
  s << "set title "
    << solve_title("contact pressure over the contact faces, seen along " + std::string(1, names[along]), info)
    << " noenhanced\n"
    << "set view map\nset size ratio -1\n" << (has_tangential(sol) ? "set key below\n" : "unset key\n") << "set grid front\n"
    << "set xlabel '" << names[a] << " (scene units)'\nset ylabel '" << names[b] << " (scene units)'\n"
    << "set pm3d interpolate 4,4\n"
    << kViridis << "set cblabel 'contact pressure (force per unit area, scene units; compression > 0)'\n";
  if (hi > lo) s << "set cbrange [" << num(lo) << ":" << num(hi) << "]\n";
  s << axis_format("x", a_lo, a_hi) << axis_format("y", b_lo, b_hi) << axis_format("cb", lo, hi);
  s << "splot 'pressure.dat' using 1:2:3:4 with pm3d notitle";
  if (has_tangential(sol)) add_stick_slip_map(f, s, sol, a, b, std::max(a_hi - a_lo, b_hi - b_lo));
  f.script = s.str();
  return f;
}

}  // namespace hemivem::app
