// The figures of an error estimate and an adaptive solve: error.png (the element indicators),
// mesh.png (a mesh's edges) and adapt.png (relative error against unknowns and run time).
#include <hemivem/app/figures.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include <hemivem/app/text_writer.hpp>
#include <hemivem/error.hpp>

#include "figure_style.hpp"

namespace hemivem::app {

using detail::cut_title;
using detail::double_quoted_escape;
using detail::kViridis;
using detail::num;
using detail::solve_title;
using detail::without_folders;

namespace {

/// error.png draws the mesh's edges over the colours up to this many elements; above it
/// they would only darken the picture.
constexpr int kMaxElementsWithEdges = 20000;

/// mesh.png zooms on its smallest element when the mesh has at least this many elements and
/// its largest element diameter is at least kZoomDiameterRatio times its smallest; the zoomed
/// square's side is kZoomDiameters smallest diameters (at most half the mesh's longer side).
constexpr int kMinElementsZoomed = 200;
constexpr double kZoomDiameterRatio = 8.0;
constexpr double kZoomDiameters = 40.0;

/// The widest range of the colour scale in decades: smaller indicators take its lowest
/// colour, like zeros.
constexpr double kMaxDecades = 12.0;

/// The mesh's bounding box with a margin of 5% of its size on each side.
Rectangle mesh_frame(const Mesh& mesh) {
  const Rectangle b = mesh.bounding_box();
  const double margin = 0.05 * std::max({b.width(), b.height(), 1e-300});
  return {b.x0 - margin, b.x1 + margin, b.y0 - margin, b.y1 + margin};
}

/// The picture's height for a frame drawn at equal axes in a picture 1000 wide: a flat body
/// gets a lower picture (as deformed.png).
int frame_height(const Rectangle& frame) {
  return static_cast<int>(std::clamp(170.0 + 720.0 * frame.height() / frame.width(), 350.0, 700.0));
}

/// The script lines that set the frame at equal axes and name the axes.
std::string frame_lines(const Rectangle& frame) {
  std::ostringstream s;
  s << "set size ratio -1\nset clip two\n"
    << "set xrange [" << num(frame.x0) << ":" << num(frame.x1) << "]\n"
    << "set yrange [" << num(frame.y0) << ":" << num(frame.y1) << "]\n"
    << axis_format("x", frame.x0, frame.x1) << axis_format("y", frame.y0, frame.y1)
    << "set xlabel 'x (scene units)'\nset ylabel 'y (scene units)'\n";
  return s.str();
}

/// A data file of mesh edges, each a block of its two end points: all edges, or the boundary's.
/// It holds its own copy of the points: the figure may outlive the mesh.
PlotData edges_data(const std::string& name, const Mesh& mesh, const detail::PlaneEdges& edges, bool boundary_only) {
  auto ends = std::make_shared<std::vector<Vec2>>();
  const detail::PlaneEdges::Visit put = [&](int v0, int v1) {
    ends->push_back(mesh.vertex(v0));
    ends->push_back(mesh.vertex(v1));
  };
  if (!boundary_only) ends->reserve(2 * edges.count);
  (boundary_only ? edges.boundary : edges.every)(put);
  return {name, [ends = std::shared_ptr<const std::vector<Vec2>>(std::move(ends)), boundary_only](std::ostream& stream) {
            TextWriter os(stream);
            os << (boundary_only ? "# x y (boundary edges, one block each)\n" : "# x y (mesh edges, one block each)\n");
            for (std::size_t i = 0; i + 1 < ends->size(); i += 2)
              os << (*ends)[i].x() << ' ' << (*ends)[i].y() << '\n'
                 << (*ends)[i + 1].x() << ' ' << (*ends)[i + 1].y() << "\n\n";
          }};
}

/// What error_polygons.dat draws: the elements' vertices and each element's value (copies:
/// the figure may outlive the mesh).
struct IndicatorPolygons {
  std::vector<Vec2> vertices;
  std::vector<int> offsets;  ///< element e: ids[offsets[e]] .. ids[offsets[e + 1] - 1]
  std::vector<int> ids;
  std::vector<double> eta;
};

/// `text` fit for a one-line gnuplot string: control characters (a newline ...) as spaces.
std::string one_line(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return text;
}

/// The colour of viridis at t in [0, 1] as "#rrggbb" (the nine samples of kViridis, linearly
/// interpolated).
std::string viridis(double t) {
  static constexpr std::array<std::uint32_t, 9> samples{0x440154, 0x472d7b, 0x3b528b, 0x2c728e, 0x21918c,
                                                        0x28ae80, 0x5ec962, 0xaddc30, 0xfde725};
  const double x = std::clamp(t, 0.0, 1.0) * 8.0;
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(x), 7);
  const double w = x - static_cast<double>(i);
  std::ostringstream s;
  s << '#' << std::hex << std::setfill('0');
  for (int shift : {16, 8, 0}) {
    const double a = (samples[i] >> shift) & 0xff, b = (samples[i + 1] >> shift) & 0xff;
    s << std::setw(2) << static_cast<int>(std::lround(a + w * (b - a)));
  }
  return s.str();
}

/// A positive range [lo, hi] of a log axis widened by a little on each side (a point on the
/// frame would be hard to see), and to a decade when it is one value.
std::pair<double, double> log_range(double lo, double hi) {
  const double decades = std::log10(hi / lo);
  const double pad = decades > 0.0 ? std::max(0.05 * decades, 0.05) : 0.5;
  return {lo * std::pow(10.0, -pad), hi * std::pow(10.0, pad)};
}

/// The tics of a log axis from lo to hi: gnuplot's (at the powers of ten) over two decades
/// and more; over fewer, 1, 2 and 5 times the powers of ten, so that more than one is labelled.
std::string log_tics(const std::string& axis, double lo, double hi) {
  if (!(lo > 0.0 && hi > lo && std::isfinite(hi) && std::log10(hi / lo) < 2.0)) return "set " + axis + "tics autofreq\n";
  std::string list;
  for (int k = static_cast<int>(std::floor(std::log10(lo))); k <= static_cast<int>(std::ceil(std::log10(hi))); ++k)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, k);
      if (v < lo || v > hi) continue;
      std::ostringstream t;
      t << std::setprecision(6) << v;
      list += (list.empty() ? "" : ", ") + gnuplot_quote(t.str()) + " " + num(v);
    }
  return "set " + axis + "tics (" + list + ")\n";
}


/// indicator_figure of the `elements` elements whose vertex loops `element(e)` gives, the
/// vertices `mesh`'s and the edges `edges`.
template <class Element>
Figure indicator_figure_of(const Mesh& mesh, int elements, const Element& element, const detail::PlaneEdges& edges,
                           const std::vector<double>& indicators, const RunInfo& info) {
  // the value drawn for element e: its indicator when finite and positive, else 0 (the scale's
  // lowest colour); an element without an entry counts as 0, and the title says so
  std::vector<double> eta(static_cast<std::size_t>(elements), 0.0);
  double hi = 0.0, lo = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < eta.size() && e < indicators.size(); ++e) {
    const double v = indicators[e];
    if (!(std::isfinite(v) && v > 0.0)) continue;
    eta[e] = v;
    hi = std::max(hi, v), lo = std::min(lo, v);
  }
  // the colour scale: the positive indicators' range (at most kMaxDecades), a decade either
  // side of one value, any range when none is positive
  if (hi == 0.0) lo = 0.1, hi = 1.0;
  else if (lo == hi) lo = hi / 10.0, hi = hi * 10.0;
  lo = std::max(lo, hi * std::pow(10.0, -kMaxDecades));
  const bool drawn_edges = indicator_draws_edges(elements);
  const Rectangle frame = mesh_frame(mesh);

  Figure f;
  f.png = "error.png";
  f.height = frame_height(frame);
  auto polygons = std::make_shared<IndicatorPolygons>();
  polygons->vertices = mesh.vertices();
  polygons->offsets.reserve(static_cast<std::size_t>(elements) + 1);
  polygons->offsets.push_back(0);
  for (int e = 0; e < elements; ++e) {
    for (int k : element(e)) polygons->ids.push_back(k);
    polygons->offsets.push_back(static_cast<int>(polygons->ids.size()));
  }
  polygons->eta = std::move(eta);
  f.data.push_back({"error_polygons.dat", [p = std::shared_ptr<const IndicatorPolygons>(std::move(polygons))](
                                              std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# x y eta_E (one block per element, its vertices counter-clockwise)\n";
                      for (std::size_t e = 0; e < p->eta.size(); ++e) {
                        const double v = p->eta[e];
                        for (int i = p->offsets[e]; i < p->offsets[e + 1]; ++i) {
                          const Vec2& q = p->vertices[static_cast<std::size_t>(p->ids[static_cast<std::size_t>(i)])];
                          os << q.x() << ' ' << q.y() << ' ' << v << '\n';
                        }
                        os << '\n';
                      }
                    }});
  if (drawn_edges) f.data.push_back(edges_data("error_edges.dat", mesh, edges, false));
  std::string what = "error indicators";
  if (indicators.size() != static_cast<std::size_t>(elements))
    what += " (" + std::to_string(indicators.size()) + " for " + std::to_string(elements) + " elements)";
  std::ostringstream s;
  s << "set title " << solve_title(what, info) << " noenhanced\n"
    << frame_lines(frame) << kViridis << "set logscale cb\n"
    << "set cbrange [" << num(lo) << ":" << num(hi) << "]\n"
    << "set cblabel 'error indicator eta_E'\nunset key\n"
    // one plot of all the polygons, a blank line between two, each filled with its value's colour
    << "plot 'error_polygons.dat' using 1:2:($3 > " << num(lo) << " ? $3 : " << num(lo)
    << ") with filledcurves closed fillcolor palette fillstyle solid 1.0 noborder notitle";
  if (drawn_edges)
    s << ", 'error_edges.dat' using 1:2 with lines lw " << num(0.5 * mesh_line_width(elements))
      << " lc rgb '#60000000' notitle";
  f.script = s.str();
  return f;
}

}  // namespace

bool indicator_draws_edges(long long elements) { return elements <= kMaxElementsWithEdges; }

Figure indicator_figure(const Mesh& mesh, const std::vector<double>& indicators, const RunInfo& info) {
  return indicator_figure_of(mesh, mesh.num_elements(), [&mesh](int e) { return mesh.element(e); },
                             detail::plane_edges(mesh), indicators, info);
}

Figure indicator_figure(const Mesh& mesh, const WholeOfPieces& whole, const std::vector<double>& indicators,
                        const RunInfo& info) {
  if (whole.cells.size() != static_cast<std::size_t>(whole.size.cells))
    throw InternalError(std::to_string(whole.cells.size()) + " elements gathered of " + std::to_string(whole.size.cells));
  return indicator_figure_of(mesh, whole.size.cells,
                             [&whole](int e) { return whole.cells[static_cast<std::size_t>(e)]; },
                             detail::plane_edges(whole), indicators, info);
}

Figure mesh_figure(const Mesh& mesh, const RunInfo& info, const std::string& what) {
  const Rectangle frame = mesh_frame(mesh);
  const int elements = mesh.num_elements();
  // a mesh refined locally: a second panel zooms on its smallest element, where a picture of
  // the whole mesh is a blot
  double d_min = 0.0, d_max = 0.0;
  int smallest = -1;
  for (int e = 0; e < elements; ++e) {
    if (smallest < 0 || mesh.diameter(e) < d_min) d_min = mesh.diameter(e), smallest = e;
    d_max = std::max(d_max, mesh.diameter(e));
  }
  const bool zoom = elements >= kMinElementsZoomed && d_min > 0.0 && d_max >= kZoomDiameterRatio * d_min;
  Rectangle box = frame;
  int in_box = elements;
  if (zoom) {
    // the square around the smallest element, moved into the mesh's bounding box
    const Rectangle b = mesh.bounding_box();
    const double half = 0.5 * std::min(kZoomDiameters * d_min, 0.5 * std::max(b.width(), b.height()));
    const Vec2 c = mesh.centroid(smallest);
    const double x0 = std::clamp(c.x() - half, b.x0, std::max(b.x0, b.x1 - 2.0 * half));
    const double y0 = std::clamp(c.y() - half, b.y0, std::max(b.y0, b.y1 - 2.0 * half));
    box = {x0, x0 + 2.0 * half, y0, y0 + 2.0 * half};
    in_box = 0;
    for (int e = 0; e < elements; ++e) {
      const Vec2 p = mesh.centroid(e);
      in_box += p.x() >= box.x0 && p.x() <= box.x1 && p.y() >= box.y0 && p.y() <= box.y1;
    }
  }
  Figure f;
  f.png = "mesh.png";
  f.height = zoom ? 700 : frame_height(frame);
  if (zoom) f.width = 1500;
  const detail::PlaneEdges mesh_edges = detail::plane_edges(mesh);
  f.data.push_back(edges_data("mesh_edges.dat", mesh, mesh_edges, false));
  f.data.push_back(edges_data("mesh_boundary.dat", mesh, mesh_edges, true));
  auto edges = [](double lw) {
    std::ostringstream p;
    p << "plot 'mesh_edges.dat' using 1:2 with lines lw " << num(lw) << " lc rgb '#3b528b' notitle, "
      << "'mesh_boundary.dat' using 1:2 with lines lw 1.5 lc rgb '#440154' notitle";
    return p.str();
  };
  std::ostringstream s;
  if (zoom) s << "set multiplot layout 1,2\n";
  s << "set title " << solve_title(cut_title(one_line(what)), info) << " noenhanced\n"
    << frame_lines(frame) << "unset key\n";
  if (zoom)
    s << "set object 1 rect from " << num(box.x0) << "," << num(box.y0) << " to " << num(box.x1) << "," << num(box.y1)
      << " front fillstyle empty border lc rgb '#d62728' lw 1.5\n";
  s << edges(mesh_line_width(elements));
  if (zoom) {
    std::ostringstream t;
    t << "the framed square enlarged: the smallest elements, " << in_box << " elements";
    s << "\nunset object 1\nset title " << gnuplot_quote(t.str()) << " noenhanced\n"
      << frame_lines(box) << "set border lc rgb '#d62728' lw 1.5\n"
      << edges(mesh_line_width(in_box)) << "\nunset multiplot";
  }
  f.script = s.str();
  return f;
}

namespace {

// A point of the convergence figure: unknowns, run time (-1: not known), error.
struct ConvergencePoint {
  double n, seconds, error;
};

// The points drawn, per series, and their ranges.
struct ConvergencePoints {
  std::vector<std::vector<ConvergencePoint>> series;
  double n_lo = 0.0, n_hi = 0.0, e_lo = 0.0, e_hi = 0.0, t_lo = 0.0, t_hi = 0.0;
  bool any = false, any_time = false;
  std::optional<ConvergencePoint> first;  // the point of fewest unknowns (largest error among them)
};

// The points drawn: error finite and > 0 and unknowns finite and > 0; a run time that is not
// finite and > 0 is left out of the second panel alone.
ConvergencePoints convergence_points(const std::vector<ConvergenceSeries>& series) {
  ConvergencePoints p;
  p.series.resize(series.size());
  for (std::size_t k = 0; k < series.size(); ++k) {
    const ConvergenceSeries& c = series[k];
    for (std::size_t i = 0; i < c.unknowns.size() && i < c.error.size(); ++i) {
      const double n = c.unknowns[i], e = c.error[i];
      if (!(std::isfinite(n) && n > 0.0 && std::isfinite(e) && e > 0.0)) continue;
      const double t = i < c.seconds.size() && std::isfinite(c.seconds[i]) && c.seconds[i] > 0.0 ? c.seconds[i] : -1.0;
      p.series[k].push_back({n, t, e});
      p.n_lo = p.any ? std::min(p.n_lo, n) : n, p.n_hi = p.any ? std::max(p.n_hi, n) : n;
      p.e_lo = p.any ? std::min(p.e_lo, e) : e, p.e_hi = p.any ? std::max(p.e_hi, e) : e;
      p.any = true;
      if (t > 0.0) {
        p.t_lo = p.any_time ? std::min(p.t_lo, t) : t, p.t_hi = p.any_time ? std::max(p.t_hi, t) : t;
        p.any_time = true;
      }
    }
  }
  for (const auto& s : p.series)
    for (const ConvergencePoint& q : s)
      if (!p.first || q.n < p.first->n || (q.n == p.first->n && q.error > p.first->error)) p.first = q;
  return p;
}

// The gnuplot curves of the series, one per series with points; `x` is the column drawn on the
// x axis; `timed`: against the run time (a series without one is only named in the key).
std::string convergence_curves(const ConvergencePoints& p, const std::vector<ConvergenceSeries>& series,
                               const std::string& x, bool timed) {
  static constexpr std::array<int, 5> kPointTypes{7, 5, 9, 13, 11};
  std::size_t drawn = 0;
  for (const auto& s : p.series) drawn += !s.empty();
  std::ostringstream c;
  std::size_t order = 0;
  for (std::size_t k = 0; k < p.series.size(); ++k) {
    if (p.series[k].empty()) continue;
    const double t = drawn > 1 ? 0.85 * static_cast<double>(order) / static_cast<double>(drawn - 1) : 0.0;
    const bool any_timed = std::any_of(p.series[k].begin(), p.series[k].end(),
                                       [](const ConvergencePoint& q) { return q.seconds > 0.0; });
    if (timed && !any_timed) {  // nothing to draw: the key still names the series
      c << (c.tellp() > 0 ? ", " : "") << "NaN with linespoints";
    } else {
      c << (c.tellp() > 0 ? ", " : "") << "$adapt_s" << k << " using " << x << ":3 with linespoints";
    }
    c << " pt " << kPointTypes[order % kPointTypes.size()] << " ps 1 lw 2 dt " << (series[k].dashed ? 2 : 1)
      << " lc rgb '" << viridis(t) << "' title " << gnuplot_quote(one_line(series[k].name)) << " noenhanced";
    ++order;
  }
  return c.str();
}

}  // namespace

Figure convergence_figure(const std::vector<ConvergenceSeries>& series, const std::string& title,
                          const std::string& png, int dimension) {
  const ConvergencePoints points = convergence_points(series);
  const double n_lo = points.n_lo, n_hi = points.n_hi;
  // the reference N^(-1/d) (h in d dimensions) through half the error of the first point, over
  // the unknowns' range
  const bool reference = points.any && n_hi > n_lo;
  const double rate = 1.0 / (dimension == 3 ? 3.0 : 2.0);
  auto slope = [rate](double n) { return std::pow(n, -rate); };
  const double ref_c = reference ? 0.5 * points.first->error / slope(points.first->n) : 0.0;
  double r_lo = points.e_lo, r_hi = points.e_hi;
  if (reference) r_lo = std::min(r_lo, ref_c * slope(n_hi)), r_hi = std::max(r_hi, ref_c * slope(n_lo));

  Figure f;
  f.png = png;
  f.width = 1400;
  f.height = 600;
  std::ostringstream s;
  s << "set multiplot layout 1,2 title \"" << double_quoted_escape(cut_title(one_line(without_folders(title))))
    << "\" noenhanced\n"
    << "set logscale xy\nset grid\nset key top right\nset ylabel 'relative error'\n";
  // the series as data blocks: unknowns, run time (-1: not known), error
  for (std::size_t k = 0; k < points.series.size(); ++k) {
    if (points.series[k].empty()) continue;
    s << "$adapt_s" << k << " << EOD\n";
    for (const ConvergencePoint& p : points.series[k]) s << num(p.n) << ' ' << num(p.seconds) << ' ' << num(p.error) << '\n';
    s << "EOD\n";
  }
  if (reference)
    s << "$adapt_ref << EOD\n"
      << num(n_lo) << ' ' << num(ref_c * slope(n_lo)) << '\n'
      << num(n_hi) << ' ' << num(ref_c * slope(n_hi)) << "\nEOD\n";
  auto ranges = [&](double x_lo, double x_hi, double y_lo, double y_hi) {
    const auto [x0, x1] = log_range(x_lo, x_hi);
    const auto [y0, y1] = log_range(y_lo, y_hi);
    s << "set xrange [" << num(x0) << ":" << num(x1) << "]\nset yrange [" << num(y0) << ":" << num(y1) << "]\n"
      << log_tics("x", x0, x1) << log_tics("y", y0, y1);
  };
  auto empty_panel = [&](const std::string& why) {
    s << "set xrange [1:10]\nset yrange [0.1:1]\nset xtics autofreq\nset ytics autofreq\nset label 1 " << gnuplot_quote(why)
      << " at graph 0.5, graph 0.5 center\nplot NaN notitle\nunset label 1\n";
  };
  // first panel: against unknowns, with the reference slope
  s << "set title 'relative error against unknowns'\nset xlabel 'free degrees of freedom N'\n";
  if (!points.any) {
    empty_panel("no error to draw");
  } else {
    ranges(n_lo, n_hi, r_lo, r_hi);
    s << "plot " << convergence_curves(points, series, "1", false);
    if (reference)
      s << ", $adapt_ref using 1:2 with lines dt 3 lw 1.5 lc rgb '#555555' title 'N^-1/" << (dimension == 3 ? 3 : 2)
        << "' noenhanced";
    s << "\n";
  }
  // second panel: against the run time
  s << "set title 'relative error against run time'\nset xlabel 'run time (s)'\n";
  if (!points.any_time) {
    empty_panel(points.any ? "no run time to draw" : "no error to draw");
  } else {
    ranges(points.t_lo, points.t_hi, points.e_lo, points.e_hi);
    s << "plot " << convergence_curves(points, series, "($2 > 0 ? $2 : NaN)", true) << "\n";
  }
  s << "unset multiplot";
  f.script = s.str();
  return f;
}

}  // namespace hemivem::app
