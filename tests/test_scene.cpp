// Scenes: the default scene, the shipped scenes, round trips, overrides and a corpus of
// bad scenes with the message and line each must produce.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <hemivem/contact/problem.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/scene/example.hpp>

#include "default_scene_text.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace hemivem {

namespace {

using test::scenes_dir;

std::vector<fs::path> shipped_scenes() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(scenes_dir()))
    if (e.path().extension() == ".toml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Scene, DefaultSceneIsExample41OnSquares64) {
  const Scene s = default_scene();
  EXPECT_EQ(s, Scene{});
  EXPECT_EQ(s.mesh.generator, "squares");
  EXPECT_EQ(s.mesh.n, 64);
  EXPECT_TRUE(s.mesh.file.empty());
  EXPECT_DOUBLE_EQ(s.material.young, 65.0);
  EXPECT_DOUBLE_EQ(s.material.poisson, 0.29);
  EXPECT_EQ(s.material.model, PlaneModel::strain);
  EXPECT_EQ(s.material.stabilization, Stabilization::two_mu);
  ASSERT_TRUE(s.contact.has_value());
  EXPECT_DOUBLE_EQ(s.contact->gap.value, 0.02);
  EXPECT_EQ(s.contact->law.name, "paper");
  EXPECT_EQ(s.contact->constraint, ConstraintKind::box);
  EXPECT_EQ(s.solver.linear, "auto");
  EXPECT_EQ(s.solver.minimizer, "ssn");
  EXPECT_DOUBLE_EQ(s.solver.tolerance, 1e-10);
  EXPECT_EQ(s.where("contact.gap"), "<default>:" + std::to_string(s.lines.at("contact.gap")));
}

// Example 4.1 as the paper states it (Feng, Han, Huang 2021, section 4), written out here
// independently of the scene: the library's example_4_1 and build_problem of the default
// scene must both be this problem.
TEST(Scene, DefaultSceneAndExample41AreThePapersProblem) {
  Scene s = default_scene();
  apply_override(s, "mesh.n=8");
  const auto built = build_problem(s);
  const Mesh mesh = make_squares(8);
  const ContactProblem example = example_4_1(mesh);
  ASSERT_TRUE(built->has_contact);
  EXPECT_EQ(built->mesh.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(built->mesh.num_elements(), mesh.num_elements());
  EXPECT_EQ(built->problem.elasticity.mesh, &built->mesh);
  EXPECT_EQ(example.elasticity.mesh, &mesh);

  const Rectangle unit{0.0, 1.0, 0.0, 1.0};
  auto side = [&](const char* name) { return select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(unit, name, 1e-8)}); };
  std::vector<int> clamped = side("left");
  for (int e : side("right")) clamped.push_back(e);
  std::sort(clamped.begin(), clamped.end());
  std::vector<int> top = side("top"), bottom = side("bottom");
  std::sort(top.begin(), top.end());
  std::sort(bottom.begin(), bottom.end());
  for (const ContactProblem* p : {static_cast<const ContactProblem*>(&built->problem), &example}) {
    EXPECT_EQ(p->elasticity.materials.model(), PlaneModel::strain);
    EXPECT_EQ(p->elasticity.materials.material(0).young, 65.0);
    EXPECT_EQ(p->elasticity.materials.material(0).poisson, 0.29);
    EXPECT_EQ(p->elasticity.stabilization, Stabilization::two_mu);
    EXPECT_FALSE(static_cast<bool>(p->elasticity.body_force));
    ASSERT_EQ(p->elasticity.dirichlet.size(), 1u);
    std::vector<int> d = p->elasticity.dirichlet[0].facets;
    std::sort(d.begin(), d.end());
    EXPECT_EQ(d, clamped);
    EXPECT_TRUE(p->elasticity.dirichlet[0].fix[0] && p->elasticity.dirichlet[0].fix[1]);
    ASSERT_EQ(p->elasticity.tractions.size(), 1u);
    std::vector<int> t = p->elasticity.tractions[0].facets;
    std::sort(t.begin(), t.end());
    EXPECT_EQ(t, top);
    EXPECT_EQ(p->elasticity.tractions[0].traction(Vec2(0.5, 1.0)), Vec2(0.0, -8.0));
    std::vector<int> c = p->parts[0].facets;
    std::sort(c.begin(), c.end());
    EXPECT_EQ(c, bottom);
    EXPECT_EQ(p->parts[0].gap(Vec2(0.3, 0.0)), 0.02);
    ASSERT_TRUE(p->parts[0].law);
    EXPECT_EQ(p->parts[0].law->name(), "paper");
    EXPECT_EQ(p->parts[0].law->alpha(), 20.0);
    EXPECT_EQ(p->parts[0].constraint, ConstraintKind::box);
  }
  // The assembled systems agree.
  const LinearSystem a = assemble(built->problem.elasticity), b = assemble(example.elasticity);
  EXPECT_EQ((a.b - b.b).norm(), 0.0);
  EXPECT_EQ(SparseMatrix(a.A - b.A).norm(), 0.0);
}

TEST(Scene, ShippedScenesParseAndBuild) {
  const auto files = shipped_scenes();
  ASSERT_GE(files.size(), 9u);
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    const Scene s = parse_scene(f);
    if (!s.mesh.file.empty()) ASSERT_TRUE(fs::exists(s.mesh.file)) << "missing mesh " << s.mesh.file;
    if (s.dimension() == 3) {  // a solid: build_problem<3> (tests/test_scene3d.cpp)
      const auto solid = build_problem<3>(s);
      EXPECT_GT(solid->mesh.num_cells(), 0);
      EXPECT_FALSE(solid->problem.elasticity.dirichlet.at(0).facets.empty());
      EXPECT_EQ(solid->has_contact, s.contact.has_value());
      continue;
    }
    const auto built = build_problem(s);
    EXPECT_GT(built->mesh.num_elements(), 0);
    const auto& held = built->problem.elasticity.dirichlet.at(0);  // edges, or points alone
    EXPECT_FALSE(held.facets.empty() && held.vertices.empty());
    EXPECT_EQ(built->has_contact, s.contact.has_value());
    if (built->has_contact) {
      EXPECT_FALSE(built->problem.parts[0].facets.empty());
      ASSERT_TRUE(built->problem.parts[0].law);
    }
    EXPECT_NO_THROW((void)assemble(built->problem.elasticity));
  }
}

TEST(Scene, PaperExampleFileEqualsDefaultScene) {
  EXPECT_EQ(parse_scene(scenes_dir() / "paper-example-4.1.toml"), default_scene());
}

// The library embeds scenes/paper-example-4.1.toml when it is built: the same bytes.
TEST(Scene, EmbeddedDefaultSceneIsTheShippedFile) {
  std::ifstream in(scenes_dir() / "paper-example-4.1.toml", std::ios::binary);
  ASSERT_TRUE(in);
  std::ostringstream file;
  file << in.rdbuf();
  EXPECT_EQ(detail::default_scene_text(), file.str());
}

TEST(Scene, ShippedVariants) {
  EXPECT_FALSE(parse_scene(scenes_dir() / "linear-elastic.toml").contact.has_value());
  const Scene sig = parse_scene(scenes_dir() / "signorini.toml");
  EXPECT_EQ(sig.contact->law.name, "zero");
  const Scene kink = parse_scene(scenes_dir() / "kinked-law.toml");
  EXPECT_EQ(kink.contact->law.name, "kinked");
  EXPECT_EQ(kink.contact->constraint, ConstraintKind::one_sided);
  for (const std::string g : {"triangles", "voronoi", "nonconvex", "distorted"})
    EXPECT_EQ(parse_scene(scenes_dir() / ("paper-example-4.1-" + g + ".toml")).mesh.generator, g);
}

TEST(Scene, SuttonScenesReadTheShippedCopiesOfSuttonsMeshes) {
  const Scene s = parse_scene(scenes_dir() / "sutton-voronoi.toml");
  const Scene t = parse_scene(scenes_dir() / "extreme" / "tiny-edges.toml");
  ASSERT_TRUE(fs::exists(s.mesh.file)) << s.mesh.file;
  ASSERT_TRUE(fs::exists(t.mesh.file)) << t.mesh.file;
  EXPECT_EQ(fs::canonical(s.mesh.file), fs::canonical(scenes_dir() / "meshes" / "sutton-voronoi-merged.poly2d"));
  EXPECT_EQ(fs::canonical(t.mesh.file), fs::canonical(scenes_dir() / "meshes" / "sutton-voronoi.poly2d"));
  // The copies are the published conversions, byte for byte, where those are beside the checkout.
  if (!test::shared_dir().empty()) {
    const auto bytes = [](const fs::path& p) {
      std::ifstream in(p, std::ios::binary);
      return std::string(std::istreambuf_iterator<char>(in), {});
    };
    for (const char* name : {"sutton-voronoi.poly2d", "sutton-voronoi-merged.poly2d"})
      EXPECT_EQ(bytes(scenes_dir() / "meshes" / name), bytes(test::shared_dir() / "meshes" / name)) << name;
  }
  const auto built = build_problem(s);
  EXPECT_EQ(built->mesh.num_vertices(), 802);
  EXPECT_EQ(built->mesh.num_elements(), 400);
  EXPECT_FALSE(built->problem.parts[0].facets.empty());
  EXPECT_FALSE(built->problem.elasticity.tractions.at(0).facets.empty());
}

TEST(Scene, RoundTripThroughToml) {
  std::vector<Scene> scenes{default_scene()};
  for (const auto& f : shipped_scenes()) scenes.push_back(parse_scene(f));
  Scene rich = default_scene();
  rich.title = "quotes \" and \\ backslashes";
  rich.body_force = {SceneScalar{0.1, {}}, SceneScalar{0.0, "-1/3 + 0.5*sin(_pi*x)"}};
  rich.material.regions.push_back({1, 200.0, 0.3});
  rich.clamped.groups = {"wall"};
  rich.clamped.segments = {{0.0, 0.0, 0.0, 1.0}};
  rich.clamped.tolerance = 1e-6;
  rich.tractions.push_back({{{}, {}, {{0.0, 1.0, 0.5, 1.0}}, 1e-8}, {SceneScalar{1e-300, {}}, SceneScalar{2.5, {}}}, {}});
  rich.tractions.push_back({{{"left"}, {}, {}, 1e-8}, {}, SceneScalar{0.0, "2*(1 - y)"}});
  rich.dirichlet.push_back({{{"bottom"}, {}, {}, 1e-8}, std::nullopt, SceneScalar{0.0, {}}});
  rich.dirichlet.push_back({{{"top"}, {}, {}, 1e-8}, SceneScalar{0.001, {}}, SceneScalar{0.0, "-0.01*x"}});
  rich.contact->gap = SceneScalar{0.0, "0.02 + 0.5*x^2"};
  rich.contact->law.name = "sawtooth";
  rich.contact->law.parameters = {{"r1", 0.015}, {"stiffness", 50.0}};
  rich.solver.max_iterations = 7;
  rich.outputs = {"vtu"};
  scenes.push_back(rich);
  Scene piecewise = default_scene();
  piecewise.contact->law = SceneLaw{"piecewise", {}, {0.0}, {{0.0}, {0.0, 0.0, 50.0}}, {{0.0}, {0.0}}};
  scenes.push_back(piecewise);
  Scene rollers = default_scene();  // [[dirichlet]] alone: nothing clamped
  rollers.clamped = BoundarySelector{{}, {}, {}, 1e-8, {}};
  rollers.dirichlet.push_back({{{"left"}, {}, {}, 1e-8}, SceneScalar{0.0, {}}, std::nullopt});
  rollers.contact.reset();
  scenes.push_back(rollers);
  Scene polygon = default_scene();
  polygon.mesh.generator = "voronoi";
  polygon.mesh.polygon = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 1.0}, {0.25, 1.5}};
  scenes.push_back(polygon);
  for (const auto& s : scenes) {
    const std::string text = to_toml(s);
    SCOPED_TRACE(text);
    const Scene back = parse_scene_string(text, "roundtrip.toml");
    EXPECT_EQ(back, s);
    EXPECT_EQ(to_toml(back), text);
  }
}

TEST(Scene, ResolvedSceneFileReadsBack) {
  const fs::path dir = fs::temp_directory_path() / ("hemivem-scene-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Scene s = parse_scene(scenes_dir() / "kinked-law.toml");
  apply_override(s, "mesh.file=" + (dir / "elsewhere.poly2d").string());
  write_scene(dir / "scene.toml", s);
  const Scene back = parse_scene(dir / "scene.toml");
  EXPECT_EQ(back, s);
  EXPECT_EQ(back.mesh.file, dir / "elsewhere.poly2d");
  fs::remove_all(dir);
}

TEST(Scene, Overrides) {
  Scene s = default_scene();
  apply_override(s, "contact.gap=0.01");
  EXPECT_DOUBLE_EQ(s.contact->gap.value, 0.01);
  EXPECT_EQ(s.lines.at("contact.gap"), 0);
  apply_override(s, "mesh.generator=voronoi");
  EXPECT_EQ(s.mesh.generator, "voronoi");
  apply_override(s, "mesh.n = 16");
  EXPECT_EQ(s.mesh.n, 16);
  apply_override(s, "solver.minimizer=bundle-dca");
  EXPECT_EQ(s.solver.minimizer, "bundle-dca");
  apply_override(s, "solver.tolerance=1e-8");
  EXPECT_DOUBLE_EQ(s.solver.tolerance, 1e-8);
  apply_override(s, "contact.law=kinked");
  apply_override(s, "contact.parameters.sigma=0.5");
  EXPECT_DOUBLE_EQ(s.contact->law.parameters.at("sigma"), 0.5);
  apply_override(s, "contact.constraint=one-sided");
  EXPECT_EQ(s.contact->constraint, ConstraintKind::one_sided);
  apply_override(s, "loads.traction[0].value=[0.0, -4.0]");
  EXPECT_DOUBLE_EQ(s.tractions.at(0).value[1].value, -4.0);
  apply_override(s, "material.model=plane-stress");
  EXPECT_EQ(s.material.model, PlaneModel::stress);
  EXPECT_EQ(s.source, "<default>");

  // A mesh file replaces the generator, a generator replaces the file.
  apply_override(s, "mesh.file=some/mesh.poly2d");
  EXPECT_TRUE(s.mesh.file.is_absolute());
  EXPECT_EQ(s.mesh.file.filename(), "mesh.poly2d");
  EXPECT_THROW(apply_override(s, "mesh.n=8"), InputError);  // n means nothing for a file mesh
  apply_override(s, "mesh.generator=squares");
  EXPECT_TRUE(s.mesh.file.empty());
  Scene blocks = parse_scene(scenes_dir() / "two-blocks.toml");  // a body's mesh, the same
  apply_override(blocks, "body[1].mesh.file=some/mesh.poly2d");
  EXPECT_TRUE(blocks.bodies[1].mesh.file.is_absolute());
  EXPECT_EQ(blocks.bodies[1].mesh.file.filename(), "mesh.poly2d");
  EXPECT_THROW(apply_override(blocks, "body[1].mesh.n=8"), InputError);
  apply_override(blocks, "body[1].mesh.generator=triangles");
  EXPECT_TRUE(blocks.bodies[1].mesh.file.empty());
  EXPECT_EQ(blocks.bodies[1].mesh.generator, "triangles");

  // Contact on a scene without it adds the default contact part.
  Scene lin = parse_scene(scenes_dir() / "linear-elastic.toml");
  apply_override(lin, "contact.gap=0.05");
  ASSERT_TRUE(lin.contact.has_value());
  EXPECT_EQ(lin.contact->boundary.sides, std::vector<std::string>{"bottom"});
  EXPECT_DOUBLE_EQ(lin.contact->gap.value, 0.05);
}

std::string override_error(std::string_view kv) {
  Scene s = default_scene();
  const Scene before = s;
  try {
    apply_override(s, kv);
  } catch (const InputError& e) {
    EXPECT_EQ(s, before) << "a failed override must leave the scene unchanged";
    return e.what();
  }
  ADD_FAILURE() << "no error for " << kv;
  return {};
}

TEST(Scene, BadOverridesNameTheKey) {
  EXPECT_NE(override_error("contact.gapp=0.1").find("unknown key 'gapp' in [contact]; did you mean 'gap'?"), std::string::npos);
  EXPECT_NE(override_error("contcat.gap=0.1").find("did you mean 'contact'?"), std::string::npos);
  EXPECT_NE(override_error("contact.gap=-1").find("contact.gap: must be >= 0"), std::string::npos);
  EXPECT_NE(override_error("contact.gap=abc").find("contact.gap: expression 'abc': Unexpected token \"abc\""),
            std::string::npos);
  EXPECT_NE(override_error("contact.gap=true").find("contact.gap: expected a number or an expression in x and y"),
            std::string::npos);
  EXPECT_NE(override_error("loads.body_force=[0, \"2*z\"]").find("loads.body_force: element 1: expression '2*z'"),
            std::string::npos);
  EXPECT_NE(override_error("mesh.n=0").find("--set mesh.n: must be between 1"), std::string::npos);
  EXPECT_NE(override_error("mesh.generator=hex").find("unknown mesh generator 'hex'"), std::string::npos);
  EXPECT_NE(override_error("contact.law=nope").find("expected one of: paper"), std::string::npos);
  EXPECT_NE(override_error("no-equals-sign").find("expected key=value"), std::string::npos);
  EXPECT_NE(override_error("loads.traction[3].value=[0,1]").find("no element 3"), std::string::npos);
}

// Overrides are applied together and validated once: their order does not matter, and an
// error names the override it comes from.
TEST(Scene, OverridesDoNotDependOnTheirOrder) {
  Scene a = default_scene(), b = default_scene();
  apply_overrides(a, {"contact.parameters.sigma=0.5", "contact.law=kinked"});
  apply_overrides(b, {"contact.law=kinked", "contact.parameters.sigma=0.5"});
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.contact->law.name, "kinked");
  EXPECT_EQ(a.contact->law.parameters.at("sigma"), 0.5);
  Scene c = default_scene(), d = default_scene();
  apply_overrides(c, {"mesh.generator=voronoi", "mesh.domain=[[0,0],[1,0],[0,1]]"});
  apply_overrides(d, {"mesh.domain=[[0,0],[1,0],[0,1]]", "mesh.generator=voronoi"});
  EXPECT_EQ(c, d);
  // the later of two values of one key wins
  Scene e = default_scene();
  apply_overrides(e, {"contact.gap=0.1", "contact.gap=0.3"});
  EXPECT_EQ(e.contact->gap.value, 0.3);
  // an error names its override, wherever it stands
  for (const auto& list : {std::vector<std::string>{"material.E=-1", "contact.gap=0.1"},
                           std::vector<std::string>{"contact.gap=0.1", "material.E=-1"}}) {
    Scene f = default_scene();
    try {
      apply_overrides(f, list);
      ADD_FAILURE() << "no error";
    } catch (const InputError& err) {
      EXPECT_EQ(err.where(), "--set material.E");
    }
  }
}

// Overrides edit the document the scene was read from: a key of the file that an override
// makes invalid is named at its own line, and every key keeps its line.
TEST(Scene, OverridesEditTheDocumentTheSceneWasReadFrom) {
  const std::string text = R"(schema_version = 1
[contact]
side = "bottom"
law = "sawtooth"
gap = 0.02
[contact.parameters]
r1 = 0.01
)";
  Scene s = parse_scene_string(text, "/some/dir/saw.toml");
  ASSERT_NE(s.document, nullptr);
  try {
    apply_overrides(s, {"contact.law=kinked"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "/some/dir/saw.toml:7") << e.what();
    EXPECT_NE(e.detail().find("'r1' is a parameter of law sawtooth, not of law 'kinked'"), std::string::npos) << e.what();
  }
  // an error in the overridden key itself names the override
  Scene t = parse_scene_string(text, "/some/dir/saw.toml");
  try {
    apply_overrides(t, {"contact.gap=-1"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "--set contact.gap") << e.what();
  }
  // lines survive, overridden keys have none, and the result is the same scene as from text
  apply_overrides(t, {"contact.parameters.r2=0.05", "mesh.n=8"});
  EXPECT_EQ(t.where("contact.law"), "/some/dir/saw.toml:4");
  EXPECT_EQ(t.where("contact.parameters.r1"), "/some/dir/saw.toml:7");
  EXPECT_EQ(t.where("mesh.n"), "/some/dir/saw.toml");
  EXPECT_EQ(t.contact->law.parameters.at("r2"), 0.05);
  EXPECT_EQ(t, parse_scene_string(text + "r2 = 0.05\n[mesh]\nn = 8\n", "/elsewhere/saw.toml"));
  // a scene changed in code is not read back from its document
  Scene u = parse_scene_string(text, "/some/dir/saw.toml");
  u.contact->gap.value = 0.07;
  apply_overrides(u, {"mesh.n=8"});
  EXPECT_EQ(u.contact->gap.value, 0.07);
  EXPECT_EQ(u.mesh.n, 8);
  // a relative mesh file of an earlier override stays where it was resolved
  Scene v = parse_scene_string(text, "/some/dir/saw.toml");
  apply_overrides(v, {"mesh.file=m.poly2d"});
  const fs::path resolved = v.mesh.file, here = fs::current_path();
  fs::current_path(fs::temp_directory_path());
  apply_overrides(v, {"contact.gap=0.03"});
  fs::current_path(here);
  EXPECT_EQ(v.mesh.file, resolved);
}

// mesh.n = [nx, ny]: nx cells along x and ny along y, written back as given; one n again
// (--n, --set mesh.n=16) means n x n.
TEST(Scene, MeshCellCountsAlongXAndY) {
  const std::string text = "schema_version = 1\n[mesh]\ngenerator = \"squares\"\nn = [16, 4]\ndomain = [0.0, 4.0, 0.0, 1.0]\n";
  Scene s = parse_scene_string(text, "wide.toml");
  EXPECT_EQ(s.mesh.n, 16);
  ASSERT_TRUE(s.mesh.ny.has_value());
  EXPECT_EQ(*s.mesh.ny, 4);
  EXPECT_EQ(s.mesh.cells(), GridSize(16, 4));
  EXPECT_EQ(s.mesh.description(), "squares n=[16, 4]");
  EXPECT_NE(to_toml(s).find("n = [16, 4]\n"), std::string::npos);
  EXPECT_EQ(parse_scene_string(to_toml(s), "wide.toml"), s);
  const auto built = build_problem(s);
  EXPECT_EQ(built->mesh.num_elements(), 64);
  EXPECT_TRUE(test::identical(built->mesh, make_squares(GridSize(16, 4), Rectangle{0.0, 4.0, 0.0, 1.0})));
  for (int e = 0; e < built->mesh.num_elements(); ++e) EXPECT_NEAR(built->mesh.area(e), 0.0625, 1e-15);
  apply_overrides(s, {"mesh.n=8"});
  EXPECT_FALSE(s.mesh.ny.has_value());
  EXPECT_EQ(s.mesh.description(), "squares n=8");
  apply_overrides(s, {"mesh.n=[2, 3]", "mesh.generator=voronoi"});
  EXPECT_EQ(s.mesh.cells(), GridSize(2, 3));
  EXPECT_EQ(build_problem(s)->mesh.num_elements(), 6);
}

// A law parameter of another law names the law that has it; suggestions come only when close.
TEST(Scene, ErrorsSuggestOnlyCloseNames) {
  const std::string sigma = override_error("contact.parameters.sigma=0.5");
  EXPECT_NE(sigma.find("'sigma' is a parameter of law kinked, not of law 'paper' (which has none)"), std::string::npos)
      << sigma;
  EXPECT_NE(override_error("contact.gapp=0.1").find("did you mean 'gap'?"), std::string::npos);
  const std::string far = override_error("contact.adhesion=1");
  EXPECT_NE(far.find("unknown key 'adhesion' in [contact]"), std::string::npos) << far;
  EXPECT_EQ(far.find("did you mean"), std::string::npos) << far;
  EXPECT_EQ(override_error("mesh.generator=hexagons").find("did you mean"), std::string::npos);
  EXPECT_NE(override_error("mesh.generator=voronio").find("did you mean 'voronoi'?"), std::string::npos);
}

TEST(Scene, ParseErrorsCarryFileLineAndColumn) {
  try {
    (void)parse_scene_string("schema_version = 1\n[mesh]\nn = = 3\n", "x.toml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().rfind("x.toml:3:", 0), 0u) << e.where();
  }
  EXPECT_THROW((void)parse_scene("/nonexistent/scene.toml"), InputError);
}

TEST(Scene, RelativeMeshPathsResolveAgainstTheSceneFolder) {
  const Scene s = parse_scene_string("schema_version = 1\n[mesh]\nfile = \"m/a.poly2d\"\n", "/some/dir/scene.toml");
  EXPECT_EQ(s.mesh.file, fs::path("/some/dir/m/a.poly2d"));
}

TEST(Scene, MaterialsByRegionAndSegments) {
  const Scene s = parse_scene_string(R"(schema_version = 1
[mesh]
generator = "squares"
n = 4
[[material.region]]
id = 0
E = 10.0
nu = 0.2
[clamped]
segments = [[0.0, 0.0, 0.0, 1.0]]
[contact]
segments = [[0.0, 0.0, 0.5, 0.0]]
)",
                                     "regions.toml");
  const auto built = build_problem(s);
  EXPECT_DOUBLE_EQ(built->problem.elasticity.materials.material(0).young, 10.0);
  EXPECT_EQ(built->problem.parts[0].facets.size(), 2u);
  EXPECT_EQ(built->problem.elasticity.dirichlet[0].facets.size(), 4u);
}

TEST(Scene, MeshFileBesideTheScene) {
  const fs::path dir = fs::temp_directory_path() / ("hemivem-scene-mesh-" + std::to_string(::getpid()));
  fs::create_directories(dir / "meshes");
  write_poly2d(dir / "meshes" / "tri.poly2d", make_triangles(4, Rectangle{0.0, 2.0, 0.0, 1.0}));
  {
    std::ofstream out(dir / "scene.toml");
    out << "schema_version = 1\n[mesh]\nfile = \"meshes/tri.poly2d\"\n[contact]\nside = \"bottom\"\n";
  }
  const Scene s = parse_scene(dir / "scene.toml");
  EXPECT_EQ(s.mesh.file, dir / "meshes" / "tri.poly2d");
  const auto built = build_problem(s);
  EXPECT_EQ(built->mesh.num_elements(), 32);
  EXPECT_EQ(built->problem.parts[0].facets.size(), 4u);  // the bottom of the bounding box [0, 2] x [0, 1]
  EXPECT_EQ(built->problem.elasticity.tractions.size(), 0u);  // no [loads]: no loads
  fs::remove_all(dir);
}

TEST(Scene, BoundaryPartsByGmshPhysicalGroup) {
  // the Gmsh-written unit square of tests/data/gmsh has the 1D groups clamped, load, contact
  const fs::path dir = fs::temp_directory_path() / ("hemivem-scene-gmsh-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    std::ofstream out(dir / "scene.toml");
    out << "schema_version = 1\n[mesh]\nfile = \"" << (test::data_dir() / "gmsh" / "unit_square_quads.msh").string()
        << "\"\n[clamped]\ngroup = \"clamped\"\n[[loads.traction]]\ngroup = \"load\"\nvalue = [0.0, -8.0]\n"
        << "[contact]\ngroup = \"contact\"\nlaw = \"paper\"\ngap = 0.02\nconstraint = \"box\"\n";
  }
  const auto built = build_problem(parse_scene(dir / "scene.toml"));
  const Rectangle unit{};
  EXPECT_EQ(built->problem.parts[0].facets,
            select_boundary_edges(built->mesh, std::vector<Segment>{rectangle_side(unit, "bottom")}));
  EXPECT_EQ(built->problem.elasticity.tractions.at(0).facets,
            select_boundary_edges(built->mesh, std::vector<Segment>{rectangle_side(unit, "top")}));
  EXPECT_FALSE(built->problem.elasticity.dirichlet.at(0).facets.empty());
  fs::remove_all(dir);
}

// A polygon domain's edges are the groups edge0, edge1, ...: the same edges as the segments.
TEST(Scene, PolygonDomainNamesItsEdges) {
  for (const std::string generator : {"voronoi", "triangles"}) {
    const Scene s = parse_scene_string("schema_version = 1\n[mesh]\ngenerator = \"" + generator +
                                           "\"\nn = 8\ndomain = [[0, 0], [2, 0], [2, 1], [0, 1.5]]\n"
                                           "[clamped]\ngroup = \"edge3\"\n[[loads.traction]]\ngroup = \"edge2\"\n"
                                           "pressure = 1.0\n[contact]\ngroup = \"edge0\"\n",
                                       "polygon.toml");
    ASSERT_EQ(s.mesh.polygon.size(), 4u);
    const auto built = build_problem(s);
    const Mesh& m = built->mesh;
    EXPECT_NEAR(m.total_area(), 2.5, 1e-12);
    auto sorted = [](std::vector<int> v) {
      std::sort(v.begin(), v.end());
      return v;
    };
    const auto bottom = select_boundary_edges(m, std::vector<Segment>{Segment{Vec2(0, 0), Vec2(2, 0), 1e-8}});
    const auto slope = select_boundary_edges(m, std::vector<Segment>{Segment{Vec2(2, 1), Vec2(0, 1.5), 1e-8}});
    const auto left = select_boundary_edges(m, std::vector<Segment>{Segment{Vec2(0, 1.5), Vec2(0, 0), 1e-8}});
    EXPECT_FALSE(bottom.empty());
    EXPECT_EQ(sorted(built->problem.parts[0].facets), sorted(bottom));
    EXPECT_EQ(sorted(built->problem.elasticity.tractions.at(0).facets), sorted(slope));
    EXPECT_EQ(sorted(built->problem.elasticity.dirichlet.at(0).facets), sorted(left));
  }
}

TEST(Scene, LawsWithParametersAndBreakpoints) {
  Scene s = default_scene();
  apply_override(s, "mesh.n=2");
  apply_override(s, "contact.law=sawtooth");
  apply_override(s, "contact.parameters.r1=0.005");
  auto built = build_problem(s);
  const auto b = built->problem.parts[0].law->breakpoints();
  EXPECT_NE(std::find(b.begin(), b.end(), 0.005), b.end());

  const Scene p = parse_scene_string(R"(schema_version = 1
[mesh]
n = 2
[contact]
side = "bottom"
law = "piecewise"
breakpoints = [0.0]
j1 = [[0.0], [0.0, 0.0, 50.0]]
j2 = [[0.0], [0.0, 1.0]]
)",
                                     "piecewise.toml");
  built = build_problem(p);
  EXPECT_DOUBLE_EQ(built->problem.parts[0].law->value(0.1), 50.0 * 0.01 - 0.1);

  try {  // j2 is not convex: rejected with the line of the law
    (void)parse_scene_string("schema_version = 1\n[contact]\nside = \"bottom\"\nlaw = \"piecewise\"\n"
                             "breakpoints = [0.0]\nj1 = [[0.0], [0.0]]\nj2 = [[0.0], [0.0, 0.0, -1.0]]\n",
                             "concave.toml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "concave.toml:4");
  }
}

// Each file of tests/data/scenes-bad starts with "# expect: FRAGMENT" and "# line: N"
// (0 when the error names no line).
TEST(Scene, BadScenesCorpus) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(test::data_dir() / "scenes-bad"))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 10u);
  for (const auto& f : files) {
    SCOPED_TRACE(f.filename().string());
    std::ifstream in(f);
    std::string l1, l2;
    std::getline(in, l1);
    std::getline(in, l2);
    ASSERT_EQ(l1.rfind("# expect: ", 0), 0u);
    ASSERT_EQ(l2.rfind("# line: ", 0), 0u);
    const std::string fragment = l1.substr(10);
    const int line = std::stoi(l2.substr(8));
    try {
      const Scene s = parse_scene(f);
      (void)build_problem(s);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      const std::string expected_where = f.string() + (line > 0 ? ":" + std::to_string(line) : std::string());
      if (fragment.rfind("syntax error", 0) == 0)
        EXPECT_EQ(e.where().rfind(expected_where + ":", 0), 0u) << e.where();
      else
        EXPECT_EQ(e.where(), expected_where);
    }
  }
}

}  // namespace
}  // namespace hemivem
