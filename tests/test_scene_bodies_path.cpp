// Loading paths of scenes of several bodies (docs/two-bodies.md, docs/paths.md): each body's
// loads and prescribed displacements at a load factor (set_load_factor on the joined problem),
// two blocks and two boxes along a path whose every step is the contact patch test's exact field
// at its t (with the path's outputs per body), and a bonded joint between two bodies with the
// delamination law loaded along a path against the global search, as tests/test_path_validation.cpp
// does for one body on a foundation.
#include <hemivem/app/path.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/error.hpp>
#include <hemivem/scene/scene.hpp>

#include <nlohmann/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "delamination_path.hpp"
#include "test_support.hpp"

using namespace hemivem;
namespace fs = std::filesystem;

namespace {


/// The rows of a CSV file as maps from its header's names to the cells' text.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::istringstream in(test::slurp(p));
  std::string line;
  std::vector<std::string> names;
  std::vector<std::map<std::string, std::string>> rows;
  const auto cells = [](const std::string& text) {
    std::vector<std::string> out;
    std::string cell;
    std::istringstream s(text);
    while (std::getline(s, cell, ',')) out.push_back(cell);
    if (!text.empty() && text.back() == ',') out.emplace_back();
    return out;
  };
  if (std::getline(in, line)) names = cells(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> c = cells(line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < names.size() && k < c.size(); ++k) row[names[k]] = c[k];
    rows.push_back(std::move(row));
  }
  return rows;
}

double number(const std::map<std::string, std::string>& row, const std::string& name) {
  const auto it = row.find(name);
  if (it == row.end() || it->second.empty()) return std::nan("");
  return std::stod(it->second);
}

// --- each body's data at t ---------------------------------------------------------------------

const std::string kHeader = "schema_version = 1\n";
// the upper block: pulled down on its top by the traction [0, -8 t], held sideways on its left
const std::string kUpper = R"([[body]]
name = "upper"
[body.mesh]
generator = "squares"
n = [4, 2]
domain = [0.0, 1.0, 0.5, 1.0]
[[body.dirichlet]]
side = "left"
ux = 0.0
[[body.loads.traction]]
side = "top"
value = [0.0, "-8*t"]
)";
// the lower block: clamped on its left, its bottom moved by -0.01 t^2 + 0.001 x, pushed on its
// right by the number -1 (times t)
const std::string kLower = R"([[body]]
name = "lower"
[body.mesh]
generator = "squares"
n = [3, 2]
domain = [0.0, 1.0, 0.0, 0.5]
[body.clamped]
side = "left"
[[body.dirichlet]]
side = "bottom"
uy = "-0.01*t^2 + 0.001*x"
[[body.loads.traction]]
side = "right"
value = [-1.0, 0.0]
)";
const std::string kInterface = R"([[contact]]
side = "upper.bottom"
against = "lower.top"
law = "zero"
)";

}  // namespace

// The joined problem holds the upper body's prescribed parts and tractions, then the lower
// body's (its [clamped] first); set_load_factor sets each from its own body's values at t,
// checked against the scene's expressions evaluated here, and leaves every facet where it was.
TEST(SceneBodiesPath, EachBodysLoadsAndPrescribedDisplacementsAtALoadFactor) {
  const Scene s = parse_scene_string(kHeader + kUpper + kLower + kInterface, "stack.toml");
  EXPECT_FALSE(scene_is_proportional(s));  // only the bodies' values mention t
  EXPECT_TRUE(scene_is_proportional(parse_scene(test::scenes_dir() / "two-blocks.toml")));
  auto built = build_problem(s);
  ContactProblem& p = built->problem;
  ASSERT_EQ(p.elasticity.tractions.size(), 2u);
  ASSERT_EQ(p.elasticity.dirichlet.size(), 3u);
  EXPECT_EQ(p.elasticity.dirichlet[0].name, "upper.dirichlet[0]");
  EXPECT_EQ(p.elasticity.dirichlet[1].name, "lower.clamped");
  EXPECT_EQ(p.elasticity.dirichlet[2].name, "lower.dirichlet[0]");
  std::vector<std::vector<int>> facets;
  for (const auto& load : p.elasticity.tractions) facets.push_back(load.facets);
  for (const auto& d : p.elasticity.dirichlet) facets.push_back(d.facets);
  facets.push_back(p.parts[0].facets);
  facets.push_back(p.parts[0].against);

  const Vec2 top(0.25, 1.0), right(1.0, 0.25), bottom(0.75, 0.0);
  for (const double t : {0.5, 2.0}) {
    SCOPED_TRACE("t = " + std::to_string(t));
    set_load_factor(s, t, p);
    // the upper body's traction [0, "-8*t"]: as written at t
    EXPECT_EQ(p.elasticity.tractions[0].traction(top), Vec2(0.0, -8.0 * t));
    EXPECT_FALSE(p.elasticity.tractions[0].pressure);
    // the lower body's traction [-1, 0]: numbers, times t
    EXPECT_EQ(p.elasticity.tractions[1].traction(right), Vec2(-t, 0.0));
    // the lower body's prescribed u_y as written at t (its free u_x reads 0)
    ASSERT_TRUE(p.elasticity.dirichlet[2].value);
    const Vec2 u = p.elasticity.dirichlet[2].value(bottom);
    EXPECT_DOUBLE_EQ(u.y(), -0.01 * t * t + 0.001 * 0.75);
    EXPECT_EQ(u.x(), 0.0);
    EXPECT_TRUE(p.elasticity.dirichlet[2].fix[1]);
    EXPECT_FALSE(p.elasticity.dirichlet[2].fix[0]);
    EXPECT_FALSE(p.elasticity.dirichlet[0].value);  // the number 0: zero at every t
    EXPECT_FALSE(p.elasticity.dirichlet[1].value);  // [clamped] stays zero
    EXPECT_FALSE(p.elasticity.body_force);
    EXPECT_DOUBLE_EQ(p.parts[0].gap(Vec2(0.5, 0.5)), 0.0);
  }
  std::vector<std::vector<int>> after;
  for (const auto& load : p.elasticity.tractions) after.push_back(load.facets);
  for (const auto& d : p.elasticity.dirichlet) after.push_back(d.facets);
  after.push_back(p.parts[0].facets);
  after.push_back(p.parts[0].against);
  EXPECT_EQ(after, facets);

  // a problem not built from this scene is refused: the same bodies in the other order (as many
  // tractions and prescribed parts, each body's in the other place), and one body's alone
  const Scene swapped = parse_scene_string(kHeader + kLower + kUpper + kInterface, "swapped.toml");
  auto other = build_problem(swapped);
  EXPECT_THROW(set_load_factor(s, 0.5, other->problem), InternalError);
  EXPECT_NO_THROW(set_load_factor(swapped, 0.5, other->problem));
  auto upper_alone = build_problem(body_scene(s, 0));
  EXPECT_THROW(set_load_factor(s, 0.5, upper_alone->problem), InternalError);
}

// A scene of several bodies takes [path], writes it back and reads it again; [adapt] is refused
// naming its key, and an adaptive solve asked for otherwise is refused when it starts.
TEST(SceneBodiesPath, ASceneOfBodiesTakesAPathAndRefusesAdapt) {
  const std::string text = kHeader + kUpper + kLower + kInterface;
  const Scene s = parse_scene_string(text + "[path]\nt = [0.5, 1.0, 1.5]\n", "stack.toml");
  ASSERT_TRUE(s.path);
  EXPECT_EQ(s.path->factors(), (std::vector<double>{0.5, 1.0, 1.5}));
  EXPECT_TRUE(parse_scene_string(to_toml(s), "again.toml") == s);
  try {
    parse_scene_string(text + "[adapt]\ntarget = 0.05\n", "stack.toml");
    FAIL() << "[adapt] accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[adapt] is not available"), std::string::npos) << e.what();
    EXPECT_NE(e.where().find("stack.toml:"), std::string::npos) << e.where();
  }
  // an adaptive solve asked for without the key (`hemivem solve --adapt`) is refused too
  Scene adaptive = parse_scene_string(text, "stack.toml");
  adaptive.adapt = SceneAdapt{};
  try {
    (void)app::run_scene(adaptive);
    FAIL() << "an adaptive solve of two bodies ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("refines the mesh of one body"), std::string::npos) << e.what();
  }
}

// --- the contact patch test along a path ---------------------------------------------------------

namespace {

// scenes/two-blocks.toml with the pressure 2 t on the upper block's top and the lower block's
// bottom moved down by 0.01 t^2, along a path; the outputs a test reads (no figures).
const std::string kBlocksPath = R"(schema_version = 1
[[body]]
name = "upper"
[body.mesh]
generator = "voronoi"
n = [5, 3]
domain = [0.0, 1.0, 0.5, 1.0]
[body.material]
E = 10.0
nu = 0.3
[[body.dirichlet]]
side = "left"
ux = 0.0
[[body.loads.traction]]
side = "top"
pressure = "2*t"

[[body]]
name = "lower"
[body.mesh]
generator = "squares"
n = [7, 3]
domain = [0.0, 1.0, 0.0, 0.5]
[body.material]
E = 4.0
nu = 0.1
[[body.dirichlet]]
side = "left"
ux = 0.0
[[body.dirichlet]]
side = "bottom"
uy = "-0.01*t^2"

[[contact]]
name = "interface"
side = "upper.bottom"
against = "lower.top"
law = "zero"

[path]
t = [0.25, 0.5, 1.0, 1.5]

[output]
write = ["result-json", "vtu", "displacement-csv", "contact-csv", "history-csv"]
)";

/// The contact patch test's field at t (plane strain, docs/two-bodies.md): sigma_yy = -2 t and
/// sigma_xx = 0 in both blocks, u_x = 0 on x = 0, u_y continuous across y = 0.5 and -0.01 t^2 on y = 0.
Vec2 blocks_exact(const Vec2& x, bool upper, double t) {
  const double p = 2.0 * t;
  const auto eps = [p](double E, double nu) { return Vec2(p * nu * (1.0 + nu) / E, -p * (1.0 - nu * nu) / E); };
  const Vec2 lo = eps(4.0, 0.1), up = eps(10.0, 0.3);
  const double base = -0.01 * t * t;
  return upper ? Vec2(up.x() * x.x(), base + lo.y() * 0.5 + up.y() * (x.y() - 0.5))
               : Vec2(lo.x() * x.x(), base + lo.y() * x.y());
}

/// Uniaxial stress sigma_zz = -2 t in each box of scenes/two-boxes-3d.toml, free lateral
/// expansion, u_z = -0.01 t^2 on z = 0.
Vec3 boxes_exact(const Vec3& x, bool upper, double t) {
  const double p = 2.0 * t;
  const auto eps = [p](double E, double nu) { return Vec3(p * nu / E, p * nu / E, -p / E); };
  const Vec3 lo = eps(4.0, 0.1), up = eps(10.0, 0.3);
  const double base = -0.01 * t * t;
  if (!upper) return Vec3(lo.x() * x.x(), lo.y() * x.y(), base + lo.z() * x.z());
  return Vec3(up.x() * x.x(), up.y() * x.y(), base + lo.z() * 0.5 + up.z() * (x.z() - 0.5));
}

/// path-displacement.csv's rows against `exact` at each row's t: the largest difference, with
/// each row's body column checked against the bodies' ranges; the frames seen in `frames`.
template <int dim, class Exact>
double worst_in_path_displacement(const fs::path& csv, const std::vector<BodyRange>& bodies, Exact exact,
                                  std::vector<double>* frames) {
  static constexpr const char* axes[] = {"x", "y", "z"};
  double worst = 0.0;
  for (const auto& row : read_csv(csv)) {
    const int v = static_cast<int>(number(row, "vertex"));
    const bool upper = bodies[0].has_vertex(v);
    EXPECT_EQ(row.at("body"), upper ? bodies[0].name : bodies[1].name) << "vertex " << v;
    Eigen::Matrix<double, dim, 1> x, u;
    for (int c = 0; c < dim; ++c) {
      x(c) = number(row, axes[c]);
      u(c) = number(row, std::string("u") + axes[c]);
    }
    const double t = number(row, "t");
    if (frames->empty() || frames->back() != t) frames->push_back(t);
    worst = std::max(worst, (u - exact(x, upper, t)).norm());
  }
  return worst;
}

}  // namespace

// Two blocks of scenes/two-blocks.toml pressed by 2 t while the lower block's bottom sinks by
// 0.01 t^2 (a load and a prescribed displacement that mention t: each step's data set by
// set_load_factor, its load joined and condensed): every step is the exact piecewise-linear
// field at its t, every pair carries the pressure 2 t, every step balances; the outputs carry
// the bodies along the path.
TEST(SceneBodiesPath, TwoBlocksAlongAPathAreExactAtEveryStep) {
  const Scene scene = parse_scene_string(kBlocksPath, "two-blocks-path.toml");
  ASSERT_FALSE(scene_is_proportional(scene));
  const app::SceneRun run = app::run_scene(scene);
  ASSERT_EQ(run.kind(), app::RunKind::path);
  ASSERT_TRUE(run.converged());
  const auto* solve = run.plane();
  ASSERT_NE(solve, nullptr);
  ASSERT_NE(run.path(), nullptr);
  const Mesh& mesh = solve->built->mesh;
  const auto& bodies = solve->built->bodies;
  ASSERT_EQ(bodies.size(), 2u);
  const PathSolution& path = *run.path();
  ASSERT_EQ(path.steps.size(), 4u);
  EXPECT_FALSE(path.proportional);
  for (const PathStep& step : path.steps) {
    SCOPED_TRACE("t = " + std::to_string(step.t));
    ASSERT_TRUE(step.converged()) << step.message;
    ASSERT_EQ(step.u.size(), 2 * mesh.num_vertices());  // every step a frame
    double worst = 0.0;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      worst = std::max(worst, (Vec2(step.u.segment<2>(2 * v)) - blocks_exact(mesh.vertex(v), bodies[0].has_vertex(v), step.t)).norm());
    EXPECT_LT(worst, 1e-10);
    ASSERT_FALSE(step.contact.empty());
    for (const ContactNode& n : step.contact) {
      EXPECT_GE(n.partner, bodies[1].first_vertex);
      EXPECT_NEAR(n.pressure(), 2.0 * step.t, 1e-10);
    }
    ASSERT_TRUE(step.forces);
    EXPECT_LT(step.forces->residual(), 1e-10);
    EXPECT_NEAR(step.applied.y(), -2.0 * step.t, 1e-12);
  }

  const fs::path dir = test::scratch("two-blocks-path");
  run.write(dir);
  const nlohmann::json r = nlohmann::json::parse(test::slurp(dir / "result.json"));
  EXPECT_EQ(r["path"]["steps"], 4);
  EXPECT_EQ(r["path"]["converged_steps"], 4);
  // each body's balance at the last step, t = 1.5: the contact on the upper body is the load on it
  ASSERT_TRUE(r["bodies"].is_array());
  ASSERT_EQ(r["bodies"].size(), 2u);
  for (const auto& b : r["bodies"]) EXPECT_LT(b["forces"]["balance_residual"].get<double>(), 1e-10) << b["name"];
  EXPECT_NEAR(r["bodies"][0]["forces"]["applied"][1].get<double>(), -3.0, 1e-10);
  EXPECT_NEAR(r["bodies"][0]["forces"]["contact"][1].get<double>(), 3.0, 1e-10);
  EXPECT_NEAR(r["bodies"][1]["forces"]["contact"][1].get<double>(), -3.0, 1e-10);
  EXPECT_NEAR(r["bodies"][1]["forces"]["reactions"]["lower.dirichlet[1]"][1].get<double>(), 3.0, 1e-10);
  // every frame's displacement in path-displacement.csv, by body, and a VTU per frame
  std::vector<double> frames;
  EXPECT_LT(worst_in_path_displacement<2>(dir / "path-displacement.csv", bodies, blocks_exact, &frames), 1e-10);
  EXPECT_EQ(frames, (std::vector<double>{0.25, 0.5, 1.0, 1.5}));
  for (const char* f : {"solution-0001.vtu", "solution-0004.vtu", "solution.pvd", "path.json", "history.csv"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  // path-contact.csv: each node's partner and the pressure 2 t
  const auto contact = read_csv(dir / "path-contact.csv");
  ASSERT_EQ(contact.size(), 4 * path.steps.back().contact.size());
  for (const auto& row : contact) {
    EXPECT_GE(number(row, "partner"), bodies[1].first_vertex);
    EXPECT_NEAR(number(row, "pressure"), 2.0 * number(row, "t"), 1e-9);
  }
  // displacement.csv is the last step's, with the bodies
  const std::string csv = test::slurp(dir / "displacement.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "vertex,x,y,ux,uy,body");
  fs::remove_all(dir);
}

// The same in three dimensions on scenes/two-boxes-3d.toml, written as the command writes a
// path (each step into the folder as it is solved): the frames of path-displacement.csv are the
// exact field at their t, the last step's too, and each body's balance closes.
TEST(SceneBodiesPath, TwoBoxesAlongAPathAreExactAtEveryStep) {
  Scene scene = parse_scene(test::scenes_dir() / "two-boxes-3d.toml");
  apply_overrides(scene, {"body[0].loads.traction[0].pressure=\"2*t\"", "body[1].dirichlet[2].uz=\"-0.01*t^2\"",
                          "path.t=[0.5, 1.0, 1.5]",
                          "output.write=[\"result-json\", \"displacement-csv\", \"contact-csv\"]"});
  ASSERT_FALSE(scene_is_proportional(scene));
  const fs::path dir = test::scratch("two-boxes-path");
  app::RunOptions options;
  options.out = dir;
  const app::SceneRun run = app::run_scene(scene, options);
  ASSERT_EQ(run.dimension(), 3);
  ASSERT_EQ(run.kind(), app::RunKind::path);
  ASSERT_TRUE(run.converged());
  const auto* solve = run.solid();
  ASSERT_NE(solve, nullptr);
  const Mesh3D& mesh = solve->built->mesh;
  const auto& bodies = solve->built->bodies;
  ASSERT_EQ(bodies.size(), 2u);
  double worst = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    worst = std::max(worst, (Vec3(solve->solution.u.segment<3>(3 * v)) - boxes_exact(mesh.vertex(v), bodies[0].has_vertex(v), 1.5)).norm());
  EXPECT_LT(worst, 1e-10);
  for (const ContactNode3D& n : solve->solution.contact) EXPECT_NEAR(n.pressure(), 3.0, 1e-10);
  EXPECT_LT(solve->solution.forces.residual(), 1e-10);

  run.write(dir);
  std::vector<double> frames;
  EXPECT_LT(worst_in_path_displacement<3>(dir / "path-displacement.csv", bodies, boxes_exact, &frames), 1e-10);
  EXPECT_EQ(frames, (std::vector<double>{0.5, 1.0, 1.5}));
  const nlohmann::json r = nlohmann::json::parse(test::slurp(dir / "result.json"));
  EXPECT_EQ(r["path"]["converged_steps"], 3);
  ASSERT_EQ(r["bodies"].size(), 2u);
  for (const auto& b : r["bodies"]) EXPECT_LT(b["forces"]["balance_residual"].get<double>(), 1e-10) << b["name"];
  EXPECT_NEAR(r["bodies"][0]["forces"]["contact"][2].get<double>(), 3.0, 1e-10);  // 2 t on the unit square
  const auto contact = read_csv(dir / "path-contact.csv");
  ASSERT_FALSE(contact.empty());
  for (const auto& row : contact) {
    EXPECT_GE(number(row, "partner"), bodies[1].first_vertex);
    EXPECT_NEAR(number(row, "pressure"), 2.0 * number(row, "t"), 1e-9);
  }
  fs::remove_all(dir);
}

// --- a bonded joint between two bodies: delamination along a path -------------------------------

namespace {

// The delamination benchmark of scenes/delamination.toml with the foundation posed as a body: the
// layer [0, 80 mm] x [10, 20 mm] (32 x 4 squares, clamped at x = 0, pulled up on its top by `mpa`
// at t = 1) bonded along y = 10 mm to a substrate of the same steel [0, 80 mm] x [0, 10 mm]
// (32 x 2 squares, clamped on its left and bottom) by the adhesive of scenes/delamination.toml,
// now a law of the separation of the two bodies: r_nu = (u_layer - u_substrate) . nu with
// nu = (0, -1), so that the separation s = -r_nu. No constraint: the bond alone holds the layer.
Scene bonded_layers(double mpa) {
  std::ostringstream text;
  text << R"(schema_version = 1
title = "Two layers bonded by the delamination law"
[[body]]
name = "layer"
[body.mesh]
generator = "squares"
n = [32, 4]
domain = [0.0, 0.08, 0.01, 0.02]
[body.material]
E = 1.378e11
nu = 0.3
model = "plane-strain"
[body.clamped]
side = "left"
[[body.loads.traction]]
side = "top"
value = [0.0, )"
       << std::to_string(mpa * 1e6) << R"(]

[[body]]
name = "substrate"
[body.mesh]
generator = "squares"
n = [32, 2]
domain = [0.0, 0.08, 0.0, 0.01]
[body.material]
E = 1.378e11
nu = 0.3
model = "plane-strain"
[body.clamped]
side = ["left", "bottom"]

[[contact]]
name = "bond"
side = "layer.bottom"
against = "substrate.top"
constraint = "none"
law = "piecewise"
breakpoints = [-2e-3, -1e-3, -5e-4, 0.0]
j = [[4e4], [1e4, -5e6, 5e9], [0.0, -1e7, 1e10], [0.0, 0.0, 3e10], [0.0]]

[solver]
minimizer = "ssn"
search = "local"
)";
  return parse_scene_string(text.str(), "bonded-layers.toml");
}


}  // namespace

// PathValidation.DelaminationLoadedFromZero with the foundation posed as a second body: loaded
// from 0 to 30 MPa in steps of 0.1 MPa (ssn from the step before), every step converges; the
// debonded pairs (separation beyond 2 mm) never become fewer as the load grows, and some debond;
// the path jumps at least twice; at 20, 26 and 30 MPa no step reaches an energy below the lowest
// critical point the global search finds at its load (the tie of the one-body test,
// 1e-9 |energy|), and at 30 MPa, past the end of the bonded branch, the path is that point: the
// same energy within the same tie.
TEST(SceneBodiesPath, ABondedJointBetweenTwoBodiesAlongAPathAgreesWithTheGlobalSearch) {
  const int lower_first = build_problem<2>(bonded_layers(30.0))->bodies.at(1).first_vertex;
  test::expect_delamination_path_above_the_global_search(bonded_layers, [lower_first](const PathStep& s) {
    for (const ContactNode& n : s.contact) ASSERT_GE(n.partner, lower_first);
  });
}
