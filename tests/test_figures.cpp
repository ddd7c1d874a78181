// The content of the solve's figures (u_nu.png, deformed.png): what the gnuplot scripts and
// their data draw, checked without running gnuplot.
#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>
#include "test_support.hpp"
#include "bench.hpp"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <regex>
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

}  // namespace
}  // namespace hemivem::app
