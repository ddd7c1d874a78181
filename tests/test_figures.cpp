// The content of the solve's figures (u_nu.png, deformed.png) and of the error estimate's and
// the adaptive solve's (error.png, mesh.png, adapt.png): what the gnuplot scripts and their
// data draw, checked without running gnuplot, and the PNGs drawn when gnuplot is installed.
#include <hemivem/app/figures.hpp>
#include <hemivem/error.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/refine.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>
#include "test_support.hpp"
#include "bench.hpp"
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace hemivem::app {
namespace {

bool have_ssn() {
  const auto names = available_minimizers();
  return std::find(names.begin(), names.end(), "ssn") != names.end();
}

/// A shipped scene on a coarser mesh, solved with eigen and ssn.
struct Solved {
  Scene scene;
  SceneSolve solved;
  RunInfo info;
  Solved(const std::string& file, const std::vector<std::string>& overrides) {
    scene = parse_scene(test::scenes_dir() / file);
    apply_overrides(scene, overrides);
    apply_override(scene, "solver.linear=eigen");
    solved = solve_scene(scene);
    info = run_info(scene, solved);
  }
  const Mesh& mesh() const { return solved.built->mesh; }
};

const Solved& hertz() {
  static const Solved s("hertz.toml", {"mesh.n=40"});
  return s;
}

/// The rows "x y" of a figure's data file.
std::vector<Vec2> points(const Figure& f, const std::string& name) {
  std::ostringstream data;
  bool found = false;
  for (const auto& d : f.data)
    if (d.name == name) d.write(data), found = true;
  EXPECT_TRUE(found) << name << " is not among the figure's data";
  std::istringstream rows(data.str());
  std::vector<Vec2> out;
  for (std::string line; std::getline(rows, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    double x = 0, y = 0;
    if (row >> x >> y) out.emplace_back(x, y);
  }
  return out;
}

/// The range [lo, hi] of `set <axis>range [lo:hi]` in a script; NaNs when it is not set.
std::pair<double, double> range(const std::string& script, const std::string& axis) {
  const std::regex re("set " + axis + "range \\[([^:\\]]+):([^\\]]+)\\]");
  std::smatch m;
  if (!std::regex_search(script, m, re)) return {NAN, NAN};
  return {std::stod(m[1]), std::stod(m[2])};
}

class Figures : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_ssn()) GTEST_SKIP() << "the ssn minimizer was not built";
  }
};

TEST_F(Figures, HertzDeformedDrawsTheCylinderAndFramesTheBody) {
  const Solved& s = hertz();
  ASSERT_TRUE(s.info.obstacle.has_value());
  const Figure d = deformed_figure(s.mesh(), s.solved.solution, s.info);
  // the block is [-1, 1] x [-1, 0]: the frame holds it with a margin, not the far part of the cylinder
  const auto [x0, x1] = range(d.script, "x");
  const auto [y0, y1] = range(d.script, "y");
  ASSERT_TRUE(std::isfinite(y1)) << d.script;
  EXPECT_LT(x0, -1.0);
  EXPECT_GT(x1, 1.0);
  EXPECT_LT(y0, -1.0);
  EXPECT_GT(y1, 0.0);
  EXPECT_LT(y1, 0.2) << "the frame follows the body, not the obstacle";
  EXPECT_GT(y0, -1.2);
  EXPECT_GT(x0, -1.2);
  EXPECT_LT(x1, 1.2);
  // the obstacle's surface is the circle of radius 1 about (0, 0.985), not x + k g nu
  const std::vector<Vec2> surface = points(d, "surface.dat");
  ASSERT_GE(surface.size(), 100u);
  for (const Vec2& p : surface) EXPECT_NEAR((p - Vec2(0.0, 0.985)).norm(), 1.0, 1e-12);
  // the drawn disk is clipped to the frame and lies inside the circle
  const std::vector<Vec2> region = points(d, "obstacle.dat");
  ASSERT_GE(region.size(), 3u);
  for (const Vec2& p : region) {
    EXPECT_GE(p.x(), x0 - 1e-12);
    EXPECT_LE(p.x(), x1 + 1e-12);
    EXPECT_GE(p.y(), y0 - 1e-12);
    EXPECT_LE(p.y(), y1 + 1e-12);
    EXPECT_LE((p - Vec2(0.0, 0.985)).norm(), 1.0 + 1e-12);
  }
  // a rigid obstacle is drawn where it is: the body at its true displacement, whose contact
  // nodes then lie on the circle or outside it (up to the tangential displacement's second-order
  // effect, far below the indentation 0.015)
  EXPECT_NE(d.script.find("at true scale"), std::string::npos) << d.script;
  EXPECT_EQ(d.script.find("foundation.dat"), std::string::npos);
  const std::vector<Vec2> nodes = points(d, "contact.dat");
  ASSERT_EQ(nodes.size(), s.solved.solution.contact.size());
  int touching = 0;
  for (const Vec2& p : nodes) {
    const double r = (p - Vec2(0.0, 0.985)).norm();
    EXPECT_GT(r, 1.0 - 1e-3);
    touching += r < 1.0 + 1e-3;
  }
  EXPECT_GT(touching, 2);
}

TEST_F(Figures, AnObstacleOutsideTheFrameIsClippedAwayAndSaidSo) {
  const Solved& s = hertz();
  RunInfo info = s.info;
  Obstacle far;
  far.shape = Obstacle::Shape::plane;
  far.point = Vec2(0.0, 5.0);
  far.normal = Vec2(0.0, -1.0);
  info.obstacle = far;
  const Figure d = deformed_figure(s.mesh(), s.solved.solution, info);
  EXPECT_TRUE(points(d, "obstacle.dat").empty());
  EXPECT_NE(d.script.find("'rigid obstacle (outside the frame)'"), std::string::npos) << d.script;
  const auto [y0, y1] = range(d.script, "y");
  EXPECT_LT(y1, 0.2) << "the frame follows the body, not the obstacle";
}

TEST_F(Figures, HalfDiskFrameHoldsTheBodyAndTheTitleNoFolder) {
  static const Solved s("half-disk-on-plane.toml", {});
  const Figure d = deformed_figure(s.mesh(), s.solved.solution, s.info);
  // the half disk spans [-1, 1] x [0, 1]; the plane y = 0.01 is cut to the frame
  const auto [x0, x1] = range(d.script, "x");
  const auto [y0, y1] = range(d.script, "y");
  ASSERT_TRUE(std::isfinite(x0)) << d.script;
  EXPECT_GT(x0, -1.2);
  EXPECT_LT(x1, 1.2);
  EXPECT_GT(y0, -0.2);
  EXPECT_LT(y1, 1.2);
  for (const Vec2& p : points(d, "obstacle.dat")) {
    EXPECT_LE(p.y(), 0.01 + 1e-12);
    EXPECT_GE(p.y(), y0 - 1e-12);
  }
  // the mesh is named by its file, not by the folders the file was found in
  EXPECT_NE(s.info.mesh.find('/'), std::string::npos) << "the scene names its mesh by a path";
  for (const Figure& f : {d, u_nu_figure(s.mesh(), s.solved.solution, s.info)}) {
    EXPECT_NE(f.script.find("half-disk.msh"), std::string::npos) << f.script;
    EXPECT_EQ(f.script.find("meshes/half-disk.msh"), std::string::npos) << f.script;
  }
}

TEST_F(Figures, TitlesHoldNoFolders) {
  const Solved& s = hertz();
  RunInfo info = s.info;
  info.mesh = "/home/someone/work/meshes/block.msh";
  info.scene_name = "Hertz (../scenes/hertz.toml)";
  for (const Figure& f : {deformed_figure(s.mesh(), s.solved.solution, info),
                          u_nu_figure(s.mesh(), s.solved.solution, info)}) {
    const auto title = f.script.substr(f.script.find("set title"));
    const std::string line = title.substr(0, title.find('\n'));
    EXPECT_EQ(line.find('/'), std::string::npos) << line;
    EXPECT_NE(line.find("block.msh"), std::string::npos) << line;
    EXPECT_NE(line.find("Hertz (hertz.toml)"), std::string::npos) << line;
  }
  // words with a slash that are not paths stay as they are
  info.scene_name = "load/unload cycle";
  info.mesh = "squares n=40";
  const std::string script = u_nu_figure(s.mesh(), s.solved.solution, info).script;
  EXPECT_NE(script.find("load/unload cycle, squares n=40"), std::string::npos) << script;
}

TEST_F(Figures, UNuAxisFollowsUNuAndClipsAFarGap) {
  const Solved& s = hertz();
  double lo = 0.0, hi = 0.0;
  for (const auto& n : s.solved.solution.contact) lo = std::min(lo, n.u_nu), hi = std::max(hi, n.u_nu);
  ASSERT_LT(lo, -0.01);  // the cylinder pushes the top down by 0.015
  const Figure u = u_nu_figure(s.mesh(), s.solved.solution, s.info);
  const auto [y0, y1] = range(u.script, "y");
  ASSERT_TRUE(std::isfinite(y1)) << u.script;
  // u_nu fills most of the axis: the gap, up to 0.8 at the block's corners, does not set it
  EXPECT_LE(y0, lo);
  EXPECT_GE(y1, hi);
  EXPECT_GT((hi - lo) / (y1 - y0), 0.3) << y0 << " " << y1;
  EXPECT_NE(u.script.find("clipped, from -0.015"), std::string::npos) << u.script;
  EXPECT_NE(u.script.find("set clip two"), std::string::npos);
}

TEST_F(Figures, BreakpointLabelsNeverShareAPlace) {
  const Solved& s = hertz();
  RunInfo info = s.info;
  info.law_breakpoints = {-0.01, -0.0099, -0.0098, -0.005, 0.0, 1e-5};
  const Figure u = u_nu_figure(s.mesh(), s.solved.solution, info);
  const auto [y0, y1] = range(u.script, "y");
  ASSERT_TRUE(std::isfinite(y1)) << u.script;
  std::vector<double> at;
  std::vector<std::string> texts;
  const std::regex re("set label '([^']*)' at graph [0-9.]+, first ([^ ]+)");
  for (std::sregex_iterator it(u.script.begin(), u.script.end(), re), end; it != end; ++it) {
    texts.push_back((*it)[1]);
    at.push_back(std::stod((*it)[2]));
  }
  ASSERT_EQ(at.size(), 3u) << u.script;
  for (std::size_t i = 0; i < at.size(); ++i)
    for (std::size_t j = i + 1; j < at.size(); ++j)
      EXPECT_GE(std::abs(at[i] - at[j]), 0.05 * (y1 - y0)) << texts[i] << " / " << texts[j];
  // each breakpoint is named once, the close ones in one label
  EXPECT_EQ(texts[0], "law breakpoints -0.01, -0.0099, -0.0098");
  EXPECT_EQ(texts[1], "law breakpoint -0.005");
  EXPECT_EQ(texts[2], "law breakpoints 0, 1e-05");
  // every breakpoint still has its line
  std::size_t arrows = 0;
  for (std::size_t p = u.script.find("set arrow"); p != std::string::npos; p = u.script.find("set arrow", p + 1)) ++arrows;
  EXPECT_EQ(arrows, info.law_breakpoints.size());
}

TEST_F(Figures, DeformedUsesAPerceptuallyUniformPalette) {
  const Solved& s = hertz();
  const std::string script = deformed_figure(s.mesh(), s.solved.solution, s.info).script;
  EXPECT_NE(script.find("set palette defined (0 '#440154'"), std::string::npos) << script;
  EXPECT_EQ(script.find("rgbformulae"), std::string::npos);
}

TEST(BenchFigure, KeyGroupsThePairsByLinearEngine) {
  using cli::BenchSeries;
  const std::vector<BenchSeries> series{{"eigen", "ssn", {{{0.1, 0.5}}, {{0.05, 2.0}}}},
                                        {"cholmod", "ssn", {{{0.1, 0.3}}}},
                                        {"eigen", "bundle-dca", {{{0.1, 0.7}}}},
                                        {"cholmod", "bundle-dca", {}}};  // no point: not drawn
  const std::string script = cli::bench_plot_script(series);
  const auto eigen = script.find("title 'linear engine eigen'");
  const auto cholmod = script.find("title 'linear engine cholmod'");
  ASSERT_NE(eigen, std::string::npos) << script;
  ASSERT_NE(cholmod, std::string::npos) << script;
  ASSERT_LT(eigen, cholmod);
  // under each heading its pairs, named by their minimizer; the eigen pairs together although
  // a cholmod pair came between them
  const auto plot = script.find("\nplot ");
  ASSERT_NE(plot, std::string::npos);
  auto entry = [&](std::size_t data, const std::string& minimizer) {
    return script.find("$d" + std::to_string(data) + " using 1:2 with linespoints", plot) != std::string::npos &&
           script.find("title '  " + minimizer + "'", script.find("$d" + std::to_string(data) + " using", plot)) !=
               std::string::npos;
  };
  EXPECT_TRUE(entry(0, "ssn"));
  EXPECT_TRUE(entry(1, "ssn"));
  EXPECT_TRUE(entry(2, "bundle-dca"));
  const auto d0 = script.find("$d0 using", plot), d1 = script.find("$d1 using", plot), d2 = script.find("$d2 using", plot);
  EXPECT_TRUE(eigen < d0 && d0 < cholmod && eigen < d2 && d2 < cholmod && cholmod < d1) << script;
  EXPECT_EQ(script.find("$d3"), std::string::npos);
  EXPECT_EQ(script.find("eigen+ssn"), std::string::npos) << "pairs are named within their group";
  EXPECT_TRUE(cli::bench_plot_script({{"eigen", "ssn", {}}}).empty());
}


// ---- error.png, mesh.png, adapt.png ----------------------------------------------------------

/// The text of a figure's data file.
std::string data_text(const Figure& f, const std::string& name) {
  std::ostringstream data;
  bool found = false;
  for (const auto& d : f.data)
    if (d.name == name) d.write(data), found = true;
  EXPECT_TRUE(found) << name << " is not among the figure's data";
  return data.str();
}

/// The blocks of numeric rows of a data file (blocks separated by blank lines; comments skipped).
std::vector<std::vector<std::vector<double>>> blocks(const std::string& text) {
  std::vector<std::vector<std::vector<double>>> out;
  std::istringstream rows(text);
  bool open = false;
  for (std::string line; std::getline(rows, line);) {
    if (!line.empty() && line[0] == '#') continue;
    if (line.empty()) {
      open = false;
      continue;
    }
    if (!open) out.emplace_back(), open = true;
    std::istringstream row(line);
    std::vector<double> values;
    for (double v; row >> v;) values.push_back(v);
    out.back().push_back(values);
  }
  return out;
}

/// Draws `figures` in a scratch folder and expects each PNG, unless gnuplot is missing.
void expect_drawn(const std::vector<Figure>& figures, const std::string& name) {
  const std::filesystem::path dir = test::scratch("figures-" + name);
  std::filesystem::create_directories(dir);
  const std::vector<std::string> reasons = draw_figures(dir, figures);
  ASSERT_EQ(reasons.size(), figures.size());
  for (std::size_t i = 0; i < figures.size(); ++i) {
    if (reasons[i] == "gnuplot not found on PATH") continue;
    EXPECT_EQ(reasons[i], "") << figures[i].png;
    EXPECT_TRUE(is_png(dir / figures[i].png)) << figures[i].png;
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

RunInfo estimate_info() {
  RunInfo info;
  info.scene_name = "adaptive test (../scenes/block.toml)";
  info.mesh = "voronoi n=6";
  return info;
}

TEST(EstimateFigures, IndicatorsFillOnePolygonPerElementWithItsValue) {
  const Mesh mesh = make_mesh("voronoi", 6);
  std::vector<double> eta(static_cast<std::size_t>(mesh.num_elements()));
  for (std::size_t e = 0; e < eta.size(); ++e) eta[e] = e % 5 == 0 ? 0.0 : std::pow(10.0, -static_cast<double>(e % 7)) * (1.0 + 0.1 * e);
  const Figure f = indicator_figure(mesh, eta, estimate_info());
  EXPECT_EQ(f.png, "error.png");
  const auto polygons = blocks(data_text(f, "error_polygons.dat"));
  ASSERT_EQ(polygons.size(), static_cast<std::size_t>(mesh.num_elements()));
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto& rows = polygons[static_cast<std::size_t>(e)];
    ASSERT_EQ(rows.size(), static_cast<std::size_t>(mesh.element_size(e))) << "element " << e;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      ASSERT_EQ(rows[k].size(), 3u);
      const Vec2& p = mesh.vertex(mesh.element(e)[k]);
      EXPECT_EQ(rows[k][0], p.x());
      EXPECT_EQ(rows[k][1], p.y());
      EXPECT_EQ(rows[k][2], eta[static_cast<std::size_t>(e)]) << "element " << e;
    }
  }
  // a logarithmic viridis scale over the positive indicators, labelled; the edges drawn
  double lo = INFINITY, hi = 0.0;
  for (double v : eta)
    if (v > 0.0) lo = std::min(lo, v), hi = std::max(hi, v);
  EXPECT_NE(f.script.find("set logscale cb"), std::string::npos) << f.script;
  EXPECT_NE(f.script.find("set palette defined (0 '#440154'"), std::string::npos);
  EXPECT_NE(f.script.find("set cblabel 'error indicator eta_E'"), std::string::npos);
  const auto [c0, c1] = range(f.script, "cb");
  EXPECT_DOUBLE_EQ(c0, lo);
  EXPECT_DOUBLE_EQ(c1, hi);
  EXPECT_NE(f.script.find("with filledcurves closed fillcolor palette"), std::string::npos);
  EXPECT_EQ(blocks(data_text(f, "error_edges.dat")).size(), mesh.edges().size());
  // the title: what, then the scene and the mesh without folders
  EXPECT_NE(f.script.find("set title \"error indicators\\nadaptive test (block.toml), voronoi n=6\""), std::string::npos)
      << f.script;
  // the frame follows the body at equal axes
  const Rectangle b = mesh.bounding_box();
  const auto [x0, x1] = range(f.script, "x");
  EXPECT_LT(x0, b.x0);
  EXPECT_GT(x0, b.x0 - 0.2 * b.width());
  EXPECT_GT(x1, b.x1);
  EXPECT_NE(f.script.find("set size ratio -1"), std::string::npos);
  expect_drawn({f}, "indicators");
}

TEST(EstimateFigures, ZeroIndicatorsKeepTheLogScale) {
  const Mesh mesh = make_mesh("squares", 4);
  // zeros among positive values: drawn with the lowest colour, the scale set by the positive ones
  std::vector<double> eta(16, 0.0);
  eta[3] = 1e-3, eta[7] = 2e-1;
  const Figure some = indicator_figure(mesh, eta, estimate_info());
  const auto [lo, hi] = range(some.script, "cb");
  EXPECT_DOUBLE_EQ(lo, 1e-3);
  EXPECT_DOUBLE_EQ(hi, 2e-1);
  EXPECT_NE(some.script.find("($3 > 0.001 ? $3 : 0.001)"), std::string::npos) << some.script;
  // all zeros, and one positive value: a positive range of the scale all the same
  for (const std::vector<double>& values : {std::vector<double>(16, 0.0), std::vector<double>{0, 0, 0, 5e-2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}}) {
    const Figure f = indicator_figure(mesh, values, estimate_info());
    const auto [a, b] = range(f.script, "cb");
    EXPECT_TRUE(std::isfinite(a) && std::isfinite(b) && a > 0.0 && b > a) << f.script;
    for (const auto& polygon : blocks(data_text(f, "error_polygons.dat")))
      for (const auto& row : polygon) EXPECT_TRUE(std::isfinite(row[2]));
  }
  // non-finite and negative indicators are drawn as zeros, not written as nan
  std::vector<double> odd(16, 1.0);
  odd[0] = NAN, odd[1] = -1.0, odd[2] = INFINITY;
  const auto polygons = blocks(data_text(indicator_figure(mesh, odd, estimate_info()), "error_polygons.dat"));
  ASSERT_EQ(polygons.size(), 16u);
  for (int e : {0, 1, 2}) EXPECT_EQ(polygons[static_cast<std::size_t>(e)][0][2], 0.0);
  expect_drawn({some, indicator_figure(mesh, std::vector<double>(16, 0.0), estimate_info())}, "zeros");
}

TEST(EstimateFigures, LargeMeshesAreFilledWithoutEdges) {
  const Mesh mesh = make_mesh("squares", 150);  // 22500 elements
  const Figure f = indicator_figure(mesh, std::vector<double>(22500, 1.0), estimate_info());
  EXPECT_EQ(f.script.find("error_edges.dat"), std::string::npos);
  for (const auto& d : f.data) EXPECT_NE(d.name, "error_edges.dat");
}

TEST(EstimateFigures, MeshFigureDrawsEveryEdge) {
  const Mesh mesh = make_mesh("voronoi", 5, Rectangle{0.0, 4.0, 0.0, 1.0});
  const Figure f = mesh_figure(mesh, estimate_info(), "final mesh, 25 elements");
  EXPECT_EQ(f.png, "mesh.png");
  EXPECT_EQ(blocks(data_text(f, "mesh_edges.dat")).size(), mesh.edges().size());
  EXPECT_EQ(blocks(data_text(f, "mesh_boundary.dat")).size(), mesh.boundary_edges().size());
  EXPECT_NE(f.script.find("set title \"final mesh, 25 elements\\n"), std::string::npos) << f.script;
  EXPECT_NE(f.script.find("set size ratio -1"), std::string::npos);
  EXPECT_LT(f.height, 700) << "a flat body gets a lower picture";
  const auto [y0, y1] = range(f.script, "y");
  EXPECT_LT(y0, 0.0);
  EXPECT_GT(y1, 1.0);
  EXPECT_LT(y1, 1.5);
  expect_drawn({f}, "mesh");
}

/// The rows of the data block `name` of a script.
std::vector<std::vector<double>> data_block(const std::string& script, const std::string& name) {
  const auto start = script.find(name + " << EOD\n");
  if (start == std::string::npos) return {};
  const auto end = script.find("EOD\n", start + name.size() + 8);
  const auto b = blocks(script.substr(start + name.size() + 8, end - start - name.size() - 8));
  return b.empty() ? std::vector<std::vector<double>>{} : b[0];
}

std::vector<ConvergenceSeries> convergence_series() {
  ConvergenceSeries adaptive{"adaptive (estimate)", {50, 120, 300, 800}, {0.01, 0.03, 0.09, 0.3}, {0.2, 0.11, 0.06, 0.03}};
  ConvergenceSeries uniform{"uniform (estimate)", {50, 200, 800, 3200}, {0.01, 0.04, 0.2, 1.1}, {0.2, 0.0, -0.1, NAN}};
  ConvergenceSeries truth{"uniform (true error)", {50, 200, 800, 3200}, {0.01, 0.0, 0.2, 1.1}, {0.25, 0.13, 0.07, 0.035}, true};
  ConvergenceSeries none{"empty series", {}, {}, {}};
  ConvergenceSeries zeros{"all zero", {10, 20}, {1, 2}, {0.0, 0.0}};
  return {adaptive, uniform, none, truth, zeros};
}

TEST(EstimateFigures, ConvergenceLeavesOutNonPositiveErrorsAndHasBothPanels) {
  const Figure f = convergence_figure(convergence_series(), "adaptive against uniform refinement");
  EXPECT_EQ(f.png, "adapt.png");
  EXPECT_EQ(convergence_figure(convergence_series(), "t", "adapt-hertz.png").png, "adapt-hertz.png");
  const std::string& s = f.script;
  EXPECT_NE(s.find("set multiplot layout 1,2 title \"adaptive against uniform refinement\""), std::string::npos) << s;
  EXPECT_NE(s.find("set logscale xy"), std::string::npos);
  std::size_t plots = 0;
  for (auto p = s.find("\nplot "); p != std::string::npos; p = s.find("\nplot ", p + 1)) ++plots;
  EXPECT_EQ(plots, 2u) << s;
  EXPECT_NE(s.find("free degrees of freedom"), std::string::npos);
  EXPECT_NE(s.find("run time (s)"), std::string::npos);
  // the uniform estimate keeps its one positive point; the series without one are left out
  const auto uniform = data_block(s, "$adapt_s1");
  ASSERT_EQ(uniform.size(), 1u) << s;
  EXPECT_EQ(uniform[0][0], 50.0);
  EXPECT_EQ(uniform[0][2], 0.2);
  EXPECT_EQ(data_block(s, "$adapt_s0").size(), 4u);
  EXPECT_EQ(data_block(s, "$adapt_s3").size(), 4u);
  EXPECT_EQ(s.find("$adapt_s2"), std::string::npos);
  EXPECT_EQ(s.find("$adapt_s4"), std::string::npos);
  EXPECT_EQ(s.find("empty series"), std::string::npos);
  EXPECT_EQ(s.find("all zero"), std::string::npos);
  // a run time of 0 stays out of the second panel only
  EXPECT_LT(data_block(s, "$adapt_s3")[1][1], 0.0);
  // every error drawn is positive; the key names the drawn series in both panels
  for (const char* block : {"$adapt_s0", "$adapt_s1", "$adapt_s3"})
    for (const auto& row : data_block(s, block)) EXPECT_GT(row[2], 0.0);
  for (const char* name : {"'adaptive (estimate)'", "'uniform (estimate)'", "'uniform (true error)'"}) {
    const auto first = s.find(name);
    ASSERT_NE(first, std::string::npos) << name;
    EXPECT_NE(s.find(name, first + 1), std::string::npos) << name << " in the second panel";
  }
  // true errors dashed, estimates solid, in viridis colours
  const auto truth = s.find("$adapt_s3 using 1:3");
  ASSERT_NE(truth, std::string::npos);
  EXPECT_NE(s.substr(truth, 120).find("dt 2"), std::string::npos) << s.substr(truth, 120);
  EXPECT_NE(s.substr(s.find("$adapt_s0 using 1:3"), 120).find("dt 1"), std::string::npos);
  EXPECT_NE(s.find("lc rgb '#440154'"), std::string::npos);
  // the reference slope in the first panel only
  const auto ref = s.find("title 'N^-1/2'");
  ASSERT_NE(ref, std::string::npos) << s;
  EXPECT_LT(ref, s.find("set title 'relative error against run time'"));
  const auto line = data_block(s, "$adapt_ref");
  ASSERT_EQ(line.size(), 2u);
  EXPECT_NEAR(std::log(line[1][1] / line[0][1]) / std::log(line[1][0] / line[0][0]), -0.5, 1e-12);
  // a solid's: N^(-1/3), h in three dimensions
  const std::string solid = convergence_figure(convergence_series(), "solid", "adapt.png", 3).script;
  EXPECT_NE(solid.find("title 'N^-1/3'"), std::string::npos) << solid;
  const auto line3 = data_block(solid, "$adapt_ref");
  ASSERT_EQ(line3.size(), 2u);
  EXPECT_NEAR(std::log(line3[1][1] / line3[0][1]) / std::log(line3[1][0] / line3[0][0]), -1.0 / 3.0, 1e-12);
  expect_drawn({f}, "convergence");
}

TEST(EstimateFigures, ConvergenceWithoutPointsStillDraws) {
  ConvergenceSeries untimed{"no timing", {10, 40}, {}, {0.3, 0.15}};
  const Figure a = convergence_figure({}, "nothing", "adapt-empty.png");
  const Figure b = convergence_figure({untimed}, "no run time", "adapt-untimed.png");
  const Figure c = convergence_figure({{"one point", {10}, {0.5}, {0.3}}}, "one point", "adapt-one.png");
  EXPECT_EQ(a.script.find("$adapt_s"), std::string::npos);
  EXPECT_NE(b.script.find("no run time to draw"), std::string::npos) << b.script;
  EXPECT_EQ(c.script.find("$adapt_ref"), std::string::npos) << "no slope from one point";
  expect_drawn({a, b, c}, "convergence-empty");
}

TEST(EstimateFigures, TitlesOfMegabytesAreCut) {
  const std::string huge(4u << 20, 'x');
  const Mesh mesh = make_mesh("squares", 3);
  RunInfo info = estimate_info();
  info.scene_name = huge;
  const std::vector<Figure> figures{indicator_figure(mesh, std::vector<double>(9, 1.0), info),
                                    mesh_figure(mesh, info, huge),
                                    convergence_figure(convergence_series(), huge + "\nsecond line")};
  for (const Figure& f : figures) {
    EXPECT_LT(f.script.size(), 5000u) << f.png;
    EXPECT_NE(f.script.find("xxx..."), std::string::npos) << f.png;
  }
  expect_drawn(figures, "huge-titles");
}

TEST(EstimateFigures, DrawnTogetherWithoutSharingDataFiles) {
  const Mesh mesh = make_mesh("squares", 3);
  RunInfo info = estimate_info();
  std::vector<std::string> names;
  for (const Figure& f : {indicator_figure(mesh, std::vector<double>(9, 1.0), info), mesh_figure(mesh, info, "mesh"),
                          convergence_figure(convergence_series(), "c")})
    for (const auto& d : f.data) names.push_back(d.name);
  for (const char* theirs : {"u_nu.dat", "edges.dat", "outline.dat", "contact.dat", "foundation.dat", "obstacle.dat", "surface.dat"})
    EXPECT_EQ(std::count(names.begin(), names.end(), theirs), 0) << theirs;
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
}

TEST(EstimateFigures, FiguresOutliveTheirMesh) {
  std::vector<Figure> figures;
  std::size_t elements = 0, edges = 0;
  {
    const Mesh mesh = make_mesh("voronoi", 4);
    elements = static_cast<std::size_t>(mesh.num_elements());
    edges = mesh.edges().size();
    figures.push_back(indicator_figure(mesh, std::vector<double>(elements, 0.5), estimate_info()));
    figures.push_back(mesh_figure(mesh, estimate_info(), "a mesh gone"));
  }
  EXPECT_EQ(blocks(data_text(figures[0], "error_polygons.dat")).size(), elements);
  EXPECT_EQ(blocks(data_text(figures[0], "error_edges.dat")).size(), edges);
  EXPECT_EQ(blocks(data_text(figures[1], "mesh_edges.dat")).size(), edges);
  expect_drawn(figures, "outlive");
}

/// The labels of the ticks gnuplot may draw from lo to hi, at a step of 1, 2 or 5 times a
/// power of ten giving up to `intervals` intervals, printed with `format` as gnuplot prints
/// them (C's printf); `extend`: also the ticks just outside, as gnuplot's autoscale extends an
/// axis to them.
std::vector<std::string> tick_labels(const std::string& format, double lo, double hi, int intervals,
                                     bool extend = false) {
  const double step = tick_step(lo, hi, intervals);
  std::vector<std::string> labels;
  const double first = extend ? std::floor(lo / step + 1e-9) : std::ceil(lo / step - 1e-9);
  const double last = extend ? std::ceil(hi / step - 1e-9) : std::floor(hi / step + 1e-9);
  for (double k = first; k <= last; k += 1.0) {
    char text[64];
    std::snprintf(text, sizeof text, format.c_str(), k * step);
    labels.emplace_back(text);
  }
  return labels;
}

/// Whether the strings of `labels` all differ.
bool distinct(const std::vector<std::string>& labels) {
  return std::set<std::string>(labels.begin(), labels.end()).size() == labels.size();
}

TEST(TickLabels, DifferAtEveryScaleFrom1eMinus12To1e6) {
  // the labels of path.png at small displacements were "-0.00000003, -0.00000003, ..."
  EXPECT_EQ(tick_format(-3.1e-8, -2.9e-8), "%.3g");
  EXPECT_EQ(tick_labels(tick_format(-3.1e-8, -2.9e-8), -3.1e-8, -2.9e-8, 4),
            (std::vector<std::string>{"-3.1e-08", "-3.05e-08", "-3e-08", "-2.95e-08", "-2.9e-08"}));
  for (double centre : {-1e6, -3.3e-8, 1e-12, 2.5e-9, 7e-5, 0.3, 1.0, 42.0, 12345.0, 1e6})
    for (double relative : {1e-9, 1e-6, 1e-3, 0.1, 1.0, 10.0}) {
      const double half = 0.5 * relative * std::abs(centre), lo = centre - half, hi = centre + half;
      const std::string format = tick_format(lo, hi);
      for (int intervals : {1, 2, 5, 10, 20}) {
        const std::vector<std::string> labels = tick_labels(format, lo, hi, intervals, true);
        ASSERT_GE(labels.size(), 2u);
        EXPECT_TRUE(distinct(labels)) << format << " from " << lo << " to " << hi << ": " << labels.front() << " ...";
        for (const auto& l : labels) EXPECT_LE(l.size(), 22u) << l;
      }
    }
  // whole numbers below 1e7 print in full; a range that is not finite or all zero, plainly
  char text[64];
  std::snprintf(text, sizeof text, tick_format(0.0, 20000.0).c_str(), 12500.0);
  EXPECT_STREQ(text, "12500");
  EXPECT_EQ(tick_format(0.0, 0.0), "%g");
  EXPECT_EQ(tick_format(0.0, NAN), "%g");
  EXPECT_EQ(axis_format("y2", -3.1e-8, -2.9e-8), "set format y2 \"%.3g\"\n");
}

TEST(TickLabels, TickStepsAreOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(tick_step(0.0, 1.0, 5), 0.2);
  EXPECT_DOUBLE_EQ(tick_step(0.0, 1.0, 1), 1.0);
  EXPECT_DOUBLE_EQ(tick_step(0.0, 0.1, 1), 0.1);
  EXPECT_DOUBLE_EQ(tick_step(0.0, 0.13, 1), 0.2);
  EXPECT_DOUBLE_EQ(tick_step(-3.1e-8, -2.9e-8, 4), 5e-10);
  EXPECT_EQ(tick_step(1.0, 1.0, 5), 0.0);
}

/// The `set format AXIS "..."` of a script, empty when not set.
std::string format_of(const std::string& script, const std::string& axis) {
  const std::regex re("set format " + axis + " \"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(script, m, re) ? std::string(m[1]) : std::string();
}

TEST_F(Figures, TinyDisplacementsGetTickLabelsThatDiffer) {
  // Example 4.1 ten orders of magnitude stiffer: u_nu of about 1e-11
  static const Solved s("paper-example-4.1.toml", {"mesh.n=8", "material.E=65e10"});
  double lo = 0.0, hi = 0.0;
  for (const auto& n : s.solved.solution.contact) lo = std::min(lo, n.u_nu), hi = std::max(hi, n.u_nu);
  ASSERT_LT(hi - lo, 1e-9);
  ASSERT_GT(hi - lo, 0.0);
  const std::string script = u_nu_figure(s.mesh(), s.solved.solution, s.info).script;
  const auto [y0, y1] = range(script, "y");
  ASSERT_TRUE(std::isfinite(y0)) << script;
  const std::string format = format_of(script, "y");
  ASSERT_FALSE(format.empty()) << script;
  for (int intervals : {2, 5, 10, 20}) EXPECT_TRUE(distinct(tick_labels(format, y0, y1, intervals))) << format;
  for (const char* axis : {"x", "y2"}) EXPECT_FALSE(format_of(script, axis).empty()) << axis << "\n" << script;
  const std::string deformed = deformed_figure(s.mesh(), s.solved.solution, s.info).script;
  EXPECT_FALSE(format_of(deformed, "cb").empty()) << deformed;  // |u| of about 1e-11
}

TEST(SolidFigures, AFlatBlockHasFewTicksOnItsShortAxis) {
  const Mesh3D mesh = make_cubes(GridSize3(8, 8, 1), Box{0.0, 1.0, 0.0, 1.0, 0.0, 0.1});
  ContactSolution3D solution;
  solution.u = Eigen::VectorXd::Zero(3 * mesh.num_vertices());
  const std::string script = deformed_figure(mesh, solution, estimate_info()).script;
  std::map<std::string, double> step;
  const std::regex re("set ([xyz])tics ([^ \\n]+)\\n");
  for (std::sregex_iterator it(script.begin(), script.end(), re), end; it != end; ++it) step[(*it)[1]] = std::stod((*it)[2]);
  ASSERT_EQ(step.size(), 3u) << script;
  // the long axes have a few ticks, the short one its two ends: no labels over each other
  EXPECT_DOUBLE_EQ(step["x"], 0.2);
  EXPECT_DOUBLE_EQ(step["y"], 0.2);
  EXPECT_GE(step["z"], 0.1);
  EXPECT_LE(0.1 / step["z"], 1.0 + 1e-12);
  for (const char* axis : {"x", "y", "z"}) EXPECT_FALSE(format_of(script, axis).empty()) << axis;
  expect_drawn({deformed_figure(mesh, solution, estimate_info())}, "flat-block");
}

/// The line width of the mesh's edges in each panel of mesh.png, in order.
std::vector<double> edge_widths(const std::string& script) {
  std::vector<double> widths;
  const std::regex re("'mesh_edges.dat' using 1:2 with lines lw ([^ ]+)");
  for (std::sregex_iterator it(script.begin(), script.end(), re), end; it != end; ++it) widths.push_back(std::stod((*it)[1]));
  return widths;
}

TEST(EstimateFigures, MeshLinesThinAsTheCellsMultiply) {
  EXPECT_EQ(mesh_line_width(16), 1.0);
  EXPECT_EQ(mesh_line_width(100), 1.0);
  EXPECT_LT(mesh_line_width(4096), mesh_line_width(1024));
  EXPECT_LT(mesh_line_width(1024), mesh_line_width(256));
  EXPECT_EQ(mesh_line_width(100000000), 0.05);
  double previous = 2.0;
  for (int n : {4, 16, 32, 64}) {
    const Mesh mesh = make_mesh("squares", n);
    const std::vector<double> widths = edge_widths(mesh_figure(mesh, estimate_info(), "mesh").script);
    ASSERT_EQ(widths.size(), 1u) << "a uniform mesh has no zoomed panel";
    EXPECT_LE(widths[0], previous);
    EXPECT_DOUBLE_EQ(widths[0], mesh_line_width(n * n));
    previous = widths[0];
  }
  EXPECT_LT(previous, 0.2);
}

TEST(EstimateFigures, ALocallyRefinedMeshIsShownWholeAndZoomedOnItsSmallestCells) {
  Mesh mesh = make_mesh("squares", 16);
  for (int level = 0; level < 4; ++level) {  // refine towards the corner (0, 0)
    int corner = 0;
    for (int e = 0; e < mesh.num_elements(); ++e)
      if (mesh.centroid(e).norm() < mesh.centroid(corner).norm()) corner = e;
    std::vector<int> marked{corner};
    mesh = refine_mesh(mesh, marked).mesh;
  }
  const Figure f = mesh_figure(mesh, estimate_info(), "final mesh");
  EXPECT_NE(f.script.find("set multiplot layout 1,2"), std::string::npos) << f.script;
  const std::regex re("set object 1 rect from ([^,]+),([^ ]+) to ([^,]+),([^ ]+) ");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(f.script, m, re)) << f.script;
  const double x0 = std::stod(m[1]), y0 = std::stod(m[2]), x1 = std::stod(m[3]), y1 = std::stod(m[4]);
  EXPECT_LE(x0, 0.0);  // the zoomed square holds the corner, and is a small part of the mesh
  EXPECT_LE(y0, 0.0);
  EXPECT_GT(x1, 0.0);
  EXPECT_LT(x1 - x0, 0.5);
  EXPECT_NEAR(x1 - x0, y1 - y0, 1e-12);
  EXPECT_EQ(range(f.script.substr(f.script.find("unset object 1")), "x"), std::make_pair(x0, x1));
  const std::vector<double> widths = edge_widths(f.script);
  ASSERT_EQ(widths.size(), 2u);
  EXPECT_DOUBLE_EQ(widths[0], mesh_line_width(mesh.num_elements()));
  EXPECT_GT(widths[1], widths[0]) << "the zoomed panel shows fewer cells, with thicker lines";
  expect_drawn({f}, "zoomed-mesh");
}

TEST(FigureFormats, EveryFigureIsAlsoAPdfAndAnSvg) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  const std::filesystem::path dir = test::scratch("figure-formats");
  std::filesystem::create_directories(dir);
  const Mesh mesh = make_mesh("voronoi", 6);
  const std::vector<Figure> figures{mesh_figure(mesh, estimate_info(), "mesh"),
                                    indicator_figure(mesh, std::vector<double>(36, 1.0), estimate_info()),
                                    convergence_figure(convergence_series(), "c")};
  const std::vector<std::string> reasons = draw_figures(dir, figures, {"png", "pdf", "svg"});
  for (std::size_t i = 0; i < figures.size(); ++i) {
    EXPECT_EQ(reasons[i], "") << figures[i].png;
    const std::vector<std::string> files = figure_files(figures[i], {"png", "pdf", "svg"});
    ASSERT_EQ(files.size(), 3u);
    EXPECT_EQ(files[0], figures[i].png);
    EXPECT_TRUE(is_png(dir / files[0])) << files[0];
    EXPECT_EQ(test::slurp(dir / files[1]).rfind("%PDF-", 0), 0u) << files[1];
    EXPECT_TRUE(is_figure_file(dir / files[2], "svg")) << files[2];
  }
  EXPECT_EQ(figure_files(figures[0], {"svg"}), std::vector<std::string>{"mesh.svg"});
  EXPECT_FALSE(is_figure_file(dir / "mesh.png", "pdf"));
  EXPECT_FALSE(is_figure_file(dir / "mesh.pdf", "svg"));
  EXPECT_THROW(draw_figures(dir, figures, {"png", "jpg"}), InputError);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

TEST(FigureWarnings, OneWarningPerReasonNamingItsFigures) {
  EXPECT_EQ(figure_warnings({{"a.png", "r1"}, {"b.png", "r2"}, {"c.png", "r1"}}),
            (std::vector<std::string>{"figure not drawn: a.png, c.png: r1", "figure not drawn: b.png: r2"}));
  EXPECT_TRUE(figure_warnings({}).empty());
}

}  // namespace
}  // namespace hemivem::app
