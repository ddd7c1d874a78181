// Loading paths in scenes (docs/reference/scenes.md): the [path] table, the load factor t in
// expressions, the obstacle's motion, friction bounds that depend on the normal contact
// (Coulomb, a table h(u_nu)), and the problem's data at a load factor (set_load_factor).
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <optional>
#include <string>

#include <hemivem/contact/problem.hpp>
#include <hemivem/error.hpp>
#include <hemivem/scene/expression.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem {
namespace {

/// The InputError that f throws (none: nullopt).
std::optional<InputError> error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

/// The error of parsing `text` as "path.toml".
InputError scene_error(const std::string& text) {
  const auto e = error_of([&] { (void)parse_scene_string(text, "path.toml"); });
  if (!e) {
    ADD_FAILURE() << "no error for:\n" << text;
    return InputError("none");
  }
  return *e;
}

/// "path.toml:N", N the line of `text` holding `needle` (1-based).
std::string line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  int line = 1;
  for (std::size_t i = 0; i < at && i < text.size(); ++i) line += text[i] == '\n';
  return "path.toml:" + std::to_string(line);
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const std::string kHead = "schema_version = 1\n";

// A block clamped on the left, pulled on the right, pressed on the top, on a foundation.
const std::string kBlock = kHead +
                           "[mesh]\nn = 4\n"
                           "[clamped]\nside = \"left\"\n"
                           "[[dirichlet]]\nside = \"right\"\nux = 0.01\n"
                           "[loads]\nbody_force = [0, \"-2*t^2\"]\n"
                           "[[loads.traction]]\nside = \"top\"\nvalue = [0, -8]\n"
                           "[[loads.traction]]\nsegments = [[0, 1, 0.5, 1]]\npressure = \"1 + x\"\n"
                           "[contact]\nside = \"bottom\"\n";

TEST(ScenePath, StepsAndDefaults) {
  const Scene none = parse_scene_string(kHead, "path.toml");
  EXPECT_FALSE(none.path.has_value());
  EXPECT_FALSE(Scene{}.path.has_value());

  const Scene s = parse_scene_string(kHead + "[path]\nsteps = 4\n", "path.toml");
  ASSERT_TRUE(s.path.has_value());
  EXPECT_EQ(s.path->steps, 4);
  EXPECT_TRUE(s.path->t.empty());
  EXPECT_EQ(s.path->frames, 100);
  EXPECT_EQ(s.path->factors(), (std::vector<double>{0.25, 0.5, 0.75, 1.0}));
  EXPECT_EQ(s.where("path.steps"), "path.toml:3");

  const Scene d = parse_scene_string(kHead + "[path]\n", "path.toml");
  ASSERT_TRUE(d.path.has_value());
  ASSERT_EQ(d.path->factors().size(), 10u);
  EXPECT_DOUBLE_EQ(d.path->factors()[2], 0.3);
  EXPECT_EQ(d.path->factors().back(), 1.0);

  const Scene t = parse_scene_string(kHead + "[path]\nt = [0.1, 0.5, 2]\nframes = 2\n", "path.toml");
  EXPECT_EQ(t.path->factors(), (std::vector<double>{0.1, 0.5, 2.0}));
  EXPECT_EQ(t.path->frames, 2);
  EXPECT_NE(s, none);
}

TEST(ScenePath, DefectsNameTheKeysLine) {
  const std::string both = kHead + "[path]\nsteps = 4\nt = [0.5, 1]\n";
  const InputError e1 = scene_error(both);
  EXPECT_EQ(e1.where(), line_of(both, "t = ")) << e1.what();
  EXPECT_TRUE(has(e1.detail(), "not both")) << e1.what();

  const std::string order = kHead + "[path]\nframes = 3\nt = [0.5, 0.25, 1]\n";
  const InputError e2 = scene_error(order);
  EXPECT_EQ(e2.where(), line_of(order, "t = ")) << e2.what();
  EXPECT_TRUE(has(e2.detail(), "path.t: element 1: the load factors must be strictly increasing")) << e2.what();
  EXPECT_TRUE(has(scene_error(kHead + "[path]\nt = [0.5, 0.5]\n").detail(), "strictly increasing"));

  const std::string zero = kHead + "[path]\nt = [0, 1]\n";
  const InputError e3 = scene_error(zero);
  EXPECT_EQ(e3.where(), line_of(zero, "t = ")) << e3.what();
  EXPECT_TRUE(has(e3.detail(), "must be > 0, got 0.0")) << e3.what();
  EXPECT_TRUE(has(scene_error(kHead + "[path]\nt = [-1, 1]\n").detail(), "must be > 0"));
  EXPECT_TRUE(has(scene_error(kHead + "[path]\nt = []\n").detail(), "at least one"));
  EXPECT_TRUE(has(scene_error(kHead + "[path]\nt = [0.5, inf]\n").detail(), "finite"));

  const std::string frames = kHead + "[path]\nsteps = 3\n\nframes = 0\n";
  const InputError e4 = scene_error(frames);
  EXPECT_EQ(e4.where(), line_of(frames, "frames")) << e4.what();
  EXPECT_TRUE(has(e4.detail(), "path.frames: must be between 1 and")) << e4.what();
  EXPECT_TRUE(has(scene_error(kHead + "[path]\nsteps = 0\n").detail(), "path.steps: must be between 1 and"));
  EXPECT_TRUE(has(scene_error(kHead + "[path]\nsteps = 2.5\n").detail(), "expected an integer"));

  const std::string unknown = kHead + "[path]\nsteps = 3\nfrmaes = 2\n";
  const InputError e5 = scene_error(unknown);
  EXPECT_EQ(e5.where(), line_of(unknown, "frmaes")) << e5.what();
  EXPECT_TRUE(has(e5.detail(), "unknown key 'frmaes' in [path]; did you mean 'frames'?")) << e5.what();
}

TEST(ScenePath, FramesAreEvenlySpreadAndIncludeTheLast) {
  ScenePath p;
  p.steps = 10;
  p.frames = 3;
  std::vector<int> frames;
  for (int k = 0; k <= 11; ++k)
    if (p.is_frame(k)) frames.push_back(k);
  EXPECT_EQ(frames, (std::vector<int>{4, 7, 10}));

  p.frames = 1;
  for (int k = 1; k < 10; ++k) EXPECT_FALSE(p.is_frame(k)) << k;
  EXPECT_TRUE(p.is_frame(10));

  p.frames = 10;  // F >= K: every step
  for (int k = 1; k <= 10; ++k) EXPECT_TRUE(p.is_frame(k)) << k;
  p.frames = 100;
  for (int k = 1; k <= 10; ++k) EXPECT_TRUE(p.is_frame(k)) << k;
  EXPECT_FALSE(p.is_frame(0));
  EXPECT_FALSE(p.is_frame(11));

  // K given by t; F frames exactly when F < K
  p.t = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
  p.frames = 4;
  int count = 0;
  for (int k = 1; k <= 7; ++k) count += p.is_frame(k);
  EXPECT_EQ(count, 4);
  EXPECT_TRUE(p.is_frame(7));
  EXPECT_FALSE(p.is_frame(8));
}

TEST(ScenePath, RoundTripsThroughToToml) {
  const std::string text = kBlock +
                           "[contact.friction]\nlaw = \"coulomb\"\ncoefficient = 0.4\n"
                           "[path]\nsteps = 7\nframes = 3\n";
  const Scene s = parse_scene_string(text, "path.toml");
  const Scene again = parse_scene_string(to_toml(s), "again.toml");
  EXPECT_EQ(again, s);
  ASSERT_TRUE(again.path.has_value());
  EXPECT_EQ(again.path->steps, 7);
  EXPECT_EQ(again.path->frames, 3);

  const std::string motion = kHead +
                             "[contact]\nside = \"bottom\"\n[contact.obstacle]\nshape = \"circle\"\n"
                             "center = [0.5, -1]\nradius = 1.0\nmotion = [0.1, \"-0.05*t^2\"]\n"
                             "[contact.friction]\nbound = [[-0.01, 0.5], [0, 1], [0.02, 1.5]]\n"
                             "[path]\nt = [0.25, 0.5, 1.5]\n";
  const Scene m = parse_scene_string(motion, "path.toml");
  ASSERT_TRUE(m.contact && m.contact->obstacle && m.contact->obstacle->motion);
  EXPECT_EQ((*m.contact->obstacle->motion)[0], (SceneScalar{0.1, {}}));
  EXPECT_EQ((*m.contact->obstacle->motion)[1], (SceneScalar{0.0, "-0.05*t^2"}));
  ASSERT_TRUE(m.contact->friction.has_value());
  EXPECT_EQ(m.contact->friction->bound_table,
            (std::vector<std::array<double, 2>>{{-0.01, 0.5}, {0.0, 1.0}, {0.02, 1.5}}));
  EXPECT_TRUE(m.contact->friction->parameters.empty());
  const std::string written = to_toml(m);
  EXPECT_TRUE(has(written, "motion = [0.1, \"-0.05*t^2\"]")) << written;
  EXPECT_TRUE(has(written, "t = [0.25, 0.5, 1.5]")) << written;
  EXPECT_EQ(parse_scene_string(written, "again.toml"), m);

  // a scene made in code
  Scene code;
  code.path = ScenePath{};
  code.path->t = {0.5, 1.0};
  code.path->frames = 1;
  code.contact->friction = SceneLaw{};
  code.contact->friction->name = "tresca";
  code.contact->friction->bound_table = {{0.0, 0.2}};
  EXPECT_EQ(parse_scene_string(to_toml(code), "code.toml"), code);
  // paths differ by their factors and frames
  ScenePath a, b;
  b.frames = 5;
  EXPECT_NE(a, b);
  b = a;
  b.steps = 4;
  EXPECT_NE(a, b);
  b.t = a.t = {1.0};
  EXPECT_EQ(a, b);  // steps unused with t
}

TEST(ScenePath, Overrides) {
  Scene s = parse_scene_string(kHead, "path.toml");
  apply_override(s, "path.steps=5");
  ASSERT_TRUE(s.path.has_value());
  EXPECT_EQ(s.path->steps, 5);
  EXPECT_EQ(s.path->factors().size(), 5u);
  apply_override(s, "path.frames=2");
  EXPECT_EQ(s.path->frames, 2);
  EXPECT_EQ(s.path->steps, 5);

  Scene code;  // made in code: written by to_toml first
  apply_override(code, "path.t=[0.5, 1]");
  ASSERT_TRUE(code.path.has_value());
  EXPECT_EQ(code.path->factors(), (std::vector<double>{0.5, 1.0}));

  Scene t = parse_scene_string(kHead + "[path]\nt = [0.5, 1]\n", "path.toml");
  // one way of giving the load factors replaces the other, as mesh.file replaces a generator
  apply_override(t, "path.steps=5");
  EXPECT_EQ(t.path->factors().size(), 5u);
  EXPECT_TRUE(t.path->t.empty());
  apply_override(t, "path.t=[0.25, 0.5]");
  EXPECT_EQ(t.path->factors(), (std::vector<double>{0.25, 0.5}));
  apply_overrides(t, {"path.t=", "path.steps=5"});
  EXPECT_EQ(t.path->factors().size(), 5u);
  const auto frames = error_of([&] { apply_override(t, "path.frames=0"); });
  ASSERT_TRUE(frames.has_value());
  EXPECT_EQ(frames->where(), "--set path.frames") << frames->what();
}

TEST(ScenePath, ExpressionsInT) {
  const ScalarExpression e = ScalarExpression::parse("-8*t^2 + x");
  EXPECT_TRUE(e.uses_t());
  EXPECT_TRUE(e.uses_position());
  EXPECT_DOUBLE_EQ(e(Vec2(1.0, 0.0), 0.5), -1.0);
  EXPECT_DOUBLE_EQ(e(Vec2(1.0, 0.0)), -7.0);  // t = 1 by default
  const ScalarExpression x = ScalarExpression::parse("2*y");
  EXPECT_FALSE(x.uses_t());
  EXPECT_TRUE(x.uses_position());
  EXPECT_DOUBLE_EQ(x(Vec2(0.0, 3.0), 0.25), 6.0);
  const ScalarExpression t = ScalarExpression::parse("0.1*t");
  EXPECT_TRUE(t.uses_t());
  EXPECT_FALSE(t.uses_position());
  EXPECT_FALSE(ScalarExpression(3.0).uses_t());
  const auto other = error_of([] { (void)ScalarExpression::parse("s*x"); });
  ASSERT_TRUE(other.has_value());
  EXPECT_TRUE(has(other->detail(), "x, y and t")) << other->what();

  // in a scene, any value may mention t
  const Scene s = parse_scene_string(kHead + "[loads]\nbody_force = [\"t\", 0]\n[contact]\nside = \"bottom\"\n"
                                             "gap = \"0.02*t\"\n",
                                     "path.toml");
  EXPECT_EQ(s.contact->gap.expression, "0.02*t");
}

TEST(ScenePath, DataAtALoadFactor) {
  const Scene s = parse_scene_string(kBlock, "path.toml");
  auto built = build_problem(s);
  ContactProblem& p = built->problem;
  const Vec2 top(0.25, 1.0);
  ASSERT_EQ(p.elasticity.tractions.size(), 2u);
  ASSERT_EQ(p.elasticity.dirichlet.size(), 2u);
  EXPECT_EQ(p.elasticity.dirichlet[1].name, "dirichlet[0]");
  // t = 1: the values as written
  EXPECT_EQ(p.elasticity.tractions[0].traction(top), Vec2(0.0, -8.0));
  EXPECT_DOUBLE_EQ(p.elasticity.tractions[1].pressure(top), 1.25);
  EXPECT_DOUBLE_EQ(p.elasticity.body_force(top).y(), -2.0);
  EXPECT_DOUBLE_EQ(p.elasticity.dirichlet[1].value(Vec2(1.0, 0.5)).x(), 0.01);
  EXPECT_DOUBLE_EQ(p.parts[0].gap(Vec2(0.5, 0.0)), 0.02);

  set_load_factor(s, 0.5, p);
  EXPECT_EQ(p.elasticity.tractions[0].traction(top), Vec2(0.0, -4.0));   // a number: times t
  EXPECT_FALSE(p.elasticity.tractions[0].pressure);
  EXPECT_DOUBLE_EQ(p.elasticity.tractions[1].pressure(top), 0.625);     // an expression without t: times t
  EXPECT_FALSE(p.elasticity.tractions[1].traction);
  EXPECT_DOUBLE_EQ(p.elasticity.body_force(top).y(), -0.5);             // -2 t^2 as written
  EXPECT_DOUBLE_EQ(p.elasticity.body_force(top).x(), 0.0);
  EXPECT_DOUBLE_EQ(p.elasticity.dirichlet[1].value(Vec2(1.0, 0.5)).x(), 0.005);
  EXPECT_DOUBLE_EQ(p.elasticity.dirichlet[1].value(Vec2(1.0, 0.5)).y(), 0.0);
  EXPECT_FALSE(p.elasticity.dirichlet[0].value);  // clamped: zero
  EXPECT_TRUE(p.elasticity.dirichlet[1].fix[0]);
  EXPECT_FALSE(p.elasticity.dirichlet[1].fix[1]);
  EXPECT_DOUBLE_EQ(p.parts[0].gap(Vec2(0.5, 0.0)), 0.02);  // a gap number stays
  EXPECT_FALSE(p.parts[0].obstacle.has_value());

  set_load_factor(s, 1.0, p);
  EXPECT_EQ(p.elasticity.tractions[0].traction(top), Vec2(0.0, -8.0));
  EXPECT_DOUBLE_EQ(p.elasticity.body_force(top).y(), -2.0);

  // a problem from another scene is refused
  const Scene other = parse_scene_string(kHead + "[mesh]\nn = 4\n[clamped]\nside = \"left\"\n", "other.toml");
  auto built_other = build_problem(other);
  EXPECT_THROW(set_load_factor(s, 0.5, built_other->problem), InternalError);
  EXPECT_THROW(set_load_factor(s, std::numeric_limits<double>::quiet_NaN(), p), InternalError);
}

TEST(ScenePath, GapsAndObstaclesAtALoadFactor) {
  const std::string gap_text = kHead + "[mesh]\nn = 4\n[clamped]\nside = \"left\"\n[contact]\nside = \"bottom\"\n"
                                       "gap = \"0.04 - 0.06*t\"\n";
  const Scene g = parse_scene_string(gap_text, "path.toml");
  auto built = build_problem(g);
  set_load_factor(g, 0.5, built->problem);
  EXPECT_DOUBLE_EQ(built->problem.parts[0].gap(Vec2(0.5, 0.0)), 0.01);
  set_load_factor(g, 1.0, built->problem);  // -0.02: refused where it is evaluated, naming the key and t
  const auto negative = error_of([&] { (void)built->problem.parts[0].gap(Vec2(0.5, 0.0)); });
  ASSERT_TRUE(negative.has_value());
  EXPECT_EQ(negative->where(), line_of(gap_text, "gap ="));
  EXPECT_TRUE(has(negative->detail(), "at t = 1.0; a gap must be finite and >= 0")) << negative->what();

  const std::string plane = kHead +
                            "[mesh]\nn = 4\n[clamped]\nside = \"left\"\n[contact]\nside = \"bottom\"\n"
                            "[contact.obstacle]\npoint = [0, -0.02]\nnormal = [0, 1]\nmotion = [0.2, 0.1]\n";
  const Scene o = parse_scene_string(plane, "path.toml");
  auto moved = build_problem(o);
  ASSERT_TRUE(moved->problem.parts[0].obstacle.has_value());
  EXPECT_DOUBLE_EQ(moved->problem.parts[0].obstacle->point.x(), 0.2);  // t = 1: moved by the motion
  EXPECT_DOUBLE_EQ(moved->problem.parts[0].obstacle->point.y(), 0.08);
  set_load_factor(o, 0.5, moved->problem);
  EXPECT_DOUBLE_EQ(moved->problem.parts[0].obstacle->point.x(), 0.1);
  EXPECT_DOUBLE_EQ(moved->problem.parts[0].obstacle->point.y(), 0.03);
  EXPECT_EQ(moved->problem.parts[0].obstacle->normal, Vec2(0.0, 1.0));
  EXPECT_FALSE(moved->problem.parts[0].gap);

  const std::string circle = kHead +
                             "[mesh]\nn = 4\n[clamped]\nside = \"left\"\n[contact]\nside = \"bottom\"\n"
                             "[contact.obstacle]\nshape = \"circle\"\ncenter = [0.5, -1]\nradius = 1.0\n"
                             "motion = [0, \"0.1*t^2\"]\n";
  const Scene c = parse_scene_string(circle, "path.toml");
  auto disk = build_problem(c);
  set_load_factor(c, 0.5, disk->problem);
  EXPECT_DOUBLE_EQ(disk->problem.parts[0].obstacle->center.y(), -0.975);  // an expression in t as written
  EXPECT_DOUBLE_EQ(disk->problem.parts[0].obstacle->center.x(), 0.5);     // the number 0: 0 at any t
  EXPECT_DOUBLE_EQ(disk->problem.parts[0].obstacle->radius, 1.0);

  const std::string poly = kHead +
                           "[mesh]\nn = 4\n[clamped]\nside = \"left\"\n[contact]\nside = \"bottom\"\n"
                           "[contact.obstacle]\nshape = \"polyline\"\npoints = [[1, -0.02], [0, -0.02]]\n"
                           "motion = [0, 0.04]\n";
  const Scene l = parse_scene_string(poly, "path.toml");
  auto line = build_problem(l);
  set_load_factor(l, 0.25, line->problem);
  ASSERT_EQ(line->problem.parts[0].obstacle->points.size(), 2u);
  EXPECT_DOUBLE_EQ(line->problem.parts[0].obstacle->points[0].y(), -0.01);
  EXPECT_DOUBLE_EQ(line->problem.parts[0].obstacle->points[1].y(), -0.01);
  EXPECT_DOUBLE_EQ(line->problem.parts[0].obstacle->points[1].x(), 0.0);
}

TEST(ScenePath, MotionIsAFunctionOfTAlone) {
  const std::string text = kHead +
                           "[contact]\nside = \"bottom\"\n[contact.obstacle]\npoint = [0, 0]\nnormal = [0, 1]\n"
                           "motion = [0, \"-0.1*t*x\"]\n";
  const InputError e = scene_error(text);
  EXPECT_EQ(e.where(), line_of(text, "motion"));
  EXPECT_TRUE(has(e.detail(), "contact.obstacle.motion: element 1: the obstacle moves as a whole")) << e.what();
  EXPECT_TRUE(has(scene_error(kHead + "[contact]\nside = \"bottom\"\n[contact.obstacle]\npoint = [0, 0]\n"
                                      "normal = [0, 1]\nmotion = [0]\n")
                      .detail(),
                  "[mx, my]"));
}

TEST(ScenePath, ProportionalScenes) {
  EXPECT_TRUE(scene_is_proportional(Scene{}));
  EXPECT_TRUE(scene_is_proportional(default_scene()));
  auto proportional = [](const std::string& text) { return scene_is_proportional(parse_scene_string(text, "p.toml")); };
  const std::string contact = "[contact]\nside = \"bottom\"\n";
  EXPECT_TRUE(proportional(kHead + "[loads]\nbody_force = [\"x\", 1]\n" + contact + "gap = \"0.01 + x\"\n"));
  EXPECT_FALSE(proportional(kBlock));  // its body force mentions t
  EXPECT_FALSE(proportional(kHead + "[[loads.traction]]\nside = \"top\"\nvalue = [0, \"-8*t\"]\n"));
  EXPECT_FALSE(proportional(kHead + "[[loads.traction]]\nside = \"top\"\npressure = \"t*t\"\n"));
  EXPECT_FALSE(proportional(kHead + "[[dirichlet]]\nside = \"top\"\nuy = \"-0.01*t\"\n"));
  EXPECT_TRUE(proportional(kHead + "[[dirichlet]]\nside = \"top\"\nuy = \"-0.01*x\"\n"));
  EXPECT_FALSE(proportional(kHead + contact + "gap = \"0.02*t\"\n"));
  const std::string obstacle = contact + "[contact.obstacle]\npoint = [0, 0]\nnormal = [0, 1]\n";
  EXPECT_TRUE(proportional(kHead + obstacle));
  EXPECT_FALSE(proportional(kHead + obstacle + "motion = [0, 0.1]\n"));
}

TEST(ScenePath, CoulombAndBoundTablesPoseAFrictionBound) {
  const std::string contact = kHead + "[mesh]\nn = 4\n[clamped]\nside = \"left\"\n[contact]\nside = \"bottom\"\n";
  const Scene c = parse_scene_string(contact + "[contact.friction]\nlaw = \"coulomb\"\ncoefficient = 0.4\n", "c.toml");
  ASSERT_TRUE(c.contact->friction.has_value());
  EXPECT_EQ(c.contact->friction->name, "coulomb");
  auto built = build_problem(c);
  ASSERT_TRUE(built->problem.parts[0].friction != nullptr);
  EXPECT_DOUBLE_EQ(built->problem.parts[0].friction->value(LawPart::j, -2.0), 2.0);  // Tresca with bound 1
  ASSERT_TRUE(built->problem.parts[0].friction_bound.has_value());
  EXPECT_EQ(built->problem.parts[0].friction_bound->kind, FrictionBound::Kind::coulomb);
  EXPECT_EQ(built->problem.parts[0].friction_bound->coefficient, 0.4);

  const Scene d = parse_scene_string(contact + "[contact.friction]\nlaw = \"coulomb\"\n", "d.toml");
  EXPECT_EQ(build_problem(d)->problem.parts[0].friction_bound->coefficient, 0.3);

  const Scene h = parse_scene_string(contact + "[contact.friction]\nlaw = \"tresca\"\nbound = [[0, 2], [0.01, 1]]\n",
                                     "h.toml");
  auto table = build_problem(h);
  EXPECT_DOUBLE_EQ(table->problem.parts[0].friction->value(LawPart::j, 3.0), 3.0);
  ASSERT_TRUE(table->problem.parts[0].friction_bound.has_value());
  EXPECT_EQ(table->problem.parts[0].friction_bound->kind, FrictionBound::Kind::normal_displacement);
  EXPECT_EQ(table->problem.parts[0].friction_bound->table, (std::vector<std::array<double, 2>>{{0.0, 2.0}, {0.01, 1.0}}));

  // a number bound: Tresca as before, no FrictionBound
  const Scene n = parse_scene_string(contact + "[contact.friction]\nbound = 0.7\n", "n.toml");
  auto plain = build_problem(n);
  EXPECT_DOUBLE_EQ(plain->problem.parts[0].friction->value(LawPart::j, 1.0), 0.7);
  EXPECT_FALSE(plain->problem.parts[0].friction_bound.has_value());
  EXPECT_FALSE(build_problem(parse_scene_string(contact, "none.toml"))->problem.parts[0].friction_bound.has_value());
}

TEST(ScenePath, FrictionBoundDefects) {
  const std::string friction = kHead + "[contact]\nside = \"bottom\"\n[contact.friction]\n";
  const std::string negative = friction + "law = \"coulomb\"\ncoefficient = -0.1\n";
  const InputError e1 = scene_error(negative);
  EXPECT_EQ(e1.where(), line_of(negative, "coefficient"));
  EXPECT_TRUE(has(e1.detail(), "contact.friction.coefficient: the friction coefficient must be finite and >= 0"))
      << e1.what();

  const std::string order = friction + "bound = [[0, 1],\n  [-1, 2]]\n";
  const InputError e2 = scene_error(order);
  EXPECT_EQ(e2.where(), line_of(order, "bound"));
  EXPECT_TRUE(has(e2.detail(), "contact.friction.bound: the points of the friction bound h(u_nu) must have increasing"))
      << e2.what();
  EXPECT_TRUE(has(scene_error(friction + "bound = [[0, -1]]\n").detail(), "h finite and >= 0"));
  EXPECT_TRUE(has(scene_error(friction + "bound = []\n").detail(), "at least one point"));
  EXPECT_TRUE(has(scene_error(friction + "bound = [[0, 1, 2]]\n").detail(), "point 1: expected [u_nu, h]"));
  EXPECT_TRUE(has(scene_error(friction + "law = \"coulomb\"\nbound = 1\n").detail(),
                  "'bound' is a parameter of friction law 'tresca', not of 'coulomb'"));
  EXPECT_TRUE(has(scene_error(friction + "coefficient = 0.3\n").detail(),
                  "'coefficient' is a parameter of friction law 'coulomb', not of 'tresca'"));
  EXPECT_TRUE(has(scene_error(friction + "law = \"slip-weakening\"\nbound = [[0, 1]]\n").detail(),
                  "'bound' is a parameter of friction law 'tresca'"));
  const std::string typo = scene_error(friction + "law = \"coulmb\"\n").detail();
  EXPECT_TRUE(has(typo, "did you mean 'coulomb'?")) << typo;
}

TEST(ScenePath, BilateralRefusesABoundThatDependsOnTheNormalContact) {
  const std::string bilateral = kHead + "[contact]\nside = \"bottom\"\nconstraint = \"bilateral\"\n[contact.friction]\n";
  const std::string coulomb = bilateral + "law = \"coulomb\"\n";
  const InputError e1 = scene_error(coulomb);
  EXPECT_EQ(e1.where(), line_of(coulomb, "law = \"coulomb\""));
  EXPECT_TRUE(has(e1.detail(), "needs the normal displacements as unknowns")) << e1.what();

  const std::string table = bilateral + "law = \"tresca\"\nbound = [[0, 1]]\n";
  const InputError e2 = scene_error(table);
  EXPECT_EQ(e2.where(), line_of(table, "bound"));
  EXPECT_TRUE(has(e2.detail(), "contact.friction.bound: a bound h(u_nu) depends on the normal contact")) << e2.what();

  // a number bound slides on a bilateral contact as before
  EXPECT_NO_THROW((void)parse_scene_string(bilateral + "bound = 0.2\n", "b.toml"));
}


// A path along which nothing changes is worth a warning; one driven by a load or a motion is not.
TEST(ScenePath, AWarningWhenThePathChangesNothing) {
  auto warned = [](const Scene& s) {
    const auto w = scene_warnings(s);
    return std::any_of(w.begin(), w.end(), [](const std::string& m) { return has(m, "every step of the path solves the same problem"); });
  };
  const std::string obstacle =
      "schema_version = 1\n[mesh]\nn = 8\n[clamped]\nside = \"bottom\"\n[contact]\nside = \"top\"\nlaw = \"zero\"\n"
      "constraint = \"one-sided\"\n[contact.obstacle]\nshape = \"circle\"\ncenter = [0.5, 1.99]\nradius = 1.0\n";
  EXPECT_TRUE(warned(parse_scene_string(obstacle + "[path]\nsteps = 4\n", "still.toml")));
  EXPECT_FALSE(warned(parse_scene_string(obstacle + "motion = [0.0, -0.01]\n[path]\nsteps = 4\n", "moving.toml")));
  EXPECT_FALSE(warned(parse_scene_string(obstacle, "static.toml")));
  EXPECT_FALSE(warned(parse_scene_string(obstacle + "[path]\nt = [1.0]\n", "one-step.toml")));
  Scene loaded = parse_scene_string(kHead + "[[loads.traction]]\nside = \"top\"\nvalue = [0.0, -8.0]\n[path]\nsteps = 4\n",
                                    "loaded.toml");
  EXPECT_FALSE(warned(loaded));
}

}  // namespace
}  // namespace hemivem
