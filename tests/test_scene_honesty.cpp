// Scenes get what they write: supports, regions, overrides that contradict each other or remove
// a key, and no gap where a bilateral contact uses none.
#include <gtest/gtest.h>

#include <hemivem/error.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "test_support.hpp"

namespace hemivem {
namespace {

using test::input_error_of;

bool has_warning(const std::vector<std::string>& warnings, const std::string& fragment) {
  return std::any_of(warnings.begin(), warnings.end(),
                     [&](const std::string& w) { return w.find(fragment) != std::string::npos; });
}

TEST(SceneSupports, AFileWithoutClampedOrDirichletHoldsNothingAndSaysSo) {
  const Scene s = parse_scene_string("schema_version = 1\n[mesh]\nn = 4\n[[loads.traction]]\nside = \"top\"\n"
                                     "value = [0, -1]\n[contact]\nside = \"bottom\"\nlaw = \"linear\"\n",
                                     "user.toml");
  EXPECT_TRUE(s.clamped.empty());
  EXPECT_TRUE(has_warning(scene_warnings(s), "no [clamped] and no [[dirichlet]]"));
  const auto built = build_problem(s);
  EXPECT_TRUE(built->problem.elasticity.dirichlet.empty());
  // the resolved scene reads back to the same scene
  EXPECT_EQ(parse_scene_string(to_toml(s), "resolved.toml"), s);
}

// two rings fitted one into the other (an interference fit): their projection onto each other
// measures an overlap, which drives the problem; the scene cannot see it before the mesh
TEST(SceneSupports, AnInterferenceFitOfTwoBodiesIsNotWarnedAboutAsUndriven) {
  const Scene s = parse_scene(test::scenes_dir() / "shrink-fit.toml");
  EXPECT_FALSE(has_warning(scene_warnings(s), "nothing drives"));
  // the same bodies paired vertex to vertex, with nothing else: nothing drives them
  Scene vertex = s;
  ASSERT_TRUE(vertex.contact.has_value());
  vertex.contact->pairing = BodyPairing::vertex;
  for (auto& c : vertex.more_contact) c.pairing = BodyPairing::vertex;
  EXPECT_TRUE(has_warning(scene_warnings(vertex), "nothing drives"));
}

TEST(SceneSupports, ThePapersSceneWritesItsSupportsAndIsNotWarnedAbout) {
  const Scene s = default_scene();
  EXPECT_EQ(s.clamped.sides, (std::vector<std::string>{"left", "right"}));
  EXPECT_GT(s.lines.count("clamped"), 0u);
  EXPECT_FALSE(has_warning(scene_warnings(s), "[clamped]"));
}

TEST(SceneRegionIds, ARegionMatchingNoElementIsAnErrorAtItsLine) {
  const Scene s = parse_scene_string("schema_version = 1\n[mesh]\nn = 2\n[clamped]\nside = \"left\"\n"
                                     "[[material.region]]\nid = 3\nE = 10.0\nnu = 0.3\n",
                                     "regions.toml");
  const std::string m = input_error_of([&] { (void)build_problem(s); });
  EXPECT_NE(m.find("regions.toml:7"), std::string::npos) << m;
  EXPECT_NE(m.find("region 3 matches no element"), std::string::npos) << m;
  EXPECT_NE(m.find("ids are 0"), std::string::npos) << m;
  // the same region selected by a box is used
  const Scene boxed = parse_scene_string("schema_version = 1\n[mesh]\nn = 2\n[clamped]\nside = \"left\"\n"
                                         "[[material.region]]\nid = 3\nE = 10.0\nnu = 0.3\nbox = [0, 0.5, 0, 1]\n",
                                         "regions.toml");
  EXPECT_NO_THROW((void)build_problem(boxed));
  // an empty box
  const Scene empty = parse_scene_string("schema_version = 1\n[mesh]\nn = 2\n[clamped]\nside = \"left\"\n"
                                         "[[material.region]]\nid = 3\nE = 10.0\nnu = 0.3\nbox = [2, 3, 2, 3]\n",
                                         "regions.toml");
  EXPECT_NE(input_error_of([&] { (void)build_problem(empty); }).find("regions.toml:7"), std::string::npos);
}

TEST(SceneRegionIds, GmshSurfaceTagsAreTheRegionIds) {
  const Mesh mesh = read_gmsh(test::data_dir() / "gmsh" / "two_regions.msh");
  EXPECT_EQ(mesh.regions(), (std::vector<int>{7, 3, 3}));  // "steel" = 7, "rubber" = 3 as in the file
  const std::filesystem::path scene_file = test::scratch("gmsh_regions.toml");
  {
    std::ofstream(scene_file) << "schema_version = 1\n[mesh]\nfile = \""
                              << (test::data_dir() / "gmsh" / "two_regions.msh").string()
                              << "\"\n[clamped]\nside = \"left\"\n[[material.region]]\nid = 7\nE = 200.0\nnu = 0.3\n"
                                 "[[material.region]]\nid = 3\nE = 1.0\nnu = 0.45\n";
  }
  const auto built = build_problem(parse_scene(scene_file));
  const MaterialTable& m = built->problem.elasticity.materials;
  EXPECT_EQ(m.material(7).young, 200.0);
  EXPECT_EQ(m.material(3).young, 1.0);
  std::filesystem::remove(scene_file);
}

TEST(SceneRegionIds, AGmshSurfaceTagBeyondTheRegionIdsIsRefusedAtItsLine) {
  std::ifstream in(test::data_dir() / "gmsh" / "two_regions.msh");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "2 1 0 0 2 1 0 1 3 0\n", to = "2 1 0 0 2 1 0 1 2000000 0\n";
  text.replace(text.find(from), from.size(), to);
  std::istringstream s(text);
  const std::string m = input_error_of([&] { (void)read_gmsh(s, "big.msh"); });
  EXPECT_NE(m.find("big.msh:18"), std::string::npos) << m;
  EXPECT_NE(m.find("2000000"), std::string::npos) << m;
}

TEST(SceneOverrides, AMeshFileAndAGeneratorKeyTogetherAreRefused) {
  Scene s = default_scene();
  std::string m = input_error_of([&] { apply_overrides(s, {"mesh.n=8", "mesh.file=x.msh"}); });
  EXPECT_NE(m.find("--set mesh.n"), std::string::npos) << m;
  EXPECT_NE(m.find("not used with mesh.file"), std::string::npos) << m;
  m = input_error_of([&] { apply_overrides(s, {"mesh.generator=squares", "mesh.file=x.msh"}); });
  EXPECT_NE(m.find("--set mesh.generator"), std::string::npos) << m;
  EXPECT_EQ(s, default_scene());
}

TEST(SceneOverrides, AnEmptyValueRemovesTheKey) {
  Scene s = default_scene();
  apply_overrides(s, {"contact.gap=", "contact.obstacle.shape=plane", "contact.obstacle.point=[0.5, -0.01]",
                      "contact.obstacle.normal=[0, 1]"});
  ASSERT_TRUE(s.contact);
  EXPECT_TRUE(s.contact->obstacle.has_value());
  Scene t = default_scene();
  apply_override(t, "contact=");
  EXPECT_FALSE(t.contact.has_value());
  const std::string m = input_error_of([&] { apply_override(t, "contact.gapp="); });
  EXPECT_NE(m.find("no key 'contact.gapp' to remove"), std::string::npos) << m;
}

TEST(SceneOverrides, MessagesNameTheKeyOnceAndTheRightOne) {
  Scene s = default_scene();
  std::string m = input_error_of([&] { apply_override(s, "solver.tolerance=2"); });
  EXPECT_EQ(m.rfind("--set solver.tolerance: must be", 0), 0u) << m;
  m = input_error_of([&] { apply_override(s, "contact.gap=1e400"); });
  EXPECT_NE(m.find("out of the range"), std::string::npos) << m;
  EXPECT_EQ(m.find("Unexpected token"), std::string::npos) << m;
  m = input_error_of([&] { apply_overrides(s, {"contact.law=kinked", "contact.parameters.sigma=-1"}); });
  EXPECT_NE(m.find("--set contact.parameters.sigma"), std::string::npos) << m;
  EXPECT_NE(m.find("stiffness"), std::string::npos) << m;
  EXPECT_EQ(m.find(" k "), std::string::npos) << m;
}

TEST(SceneBilateral, NoGapIsReportedAndAGivenGapIsWarnedAbout) {
  const std::string text = "schema_version = 1\n[mesh]\nn = 4\n[clamped]\nside = [\"left\", \"right\"]\n"
                           "[[loads.traction]]\nside = \"top\"\nvalue = [1, -1]\n[contact]\nside = \"bottom\"\n"
                           "constraint = \"bilateral\"\n";
  const Scene plain = parse_scene_string(text, "b.toml");
  EXPECT_FALSE(has_warning(scene_warnings(plain), "contact.gap"));
  EXPECT_EQ(parse_scene_string(to_toml(plain), "r.toml"), plain);
  EXPECT_FALSE(has_warning(scene_warnings(parse_scene_string(to_toml(plain), "r.toml")), "contact.gap"));
  const Scene with_gap = parse_scene_string(text + "gap = 0.05\n", "b.toml");
  EXPECT_TRUE(has_warning(scene_warnings(with_gap), "b.toml:12: contact.gap is not used"));
}

}  // namespace
}  // namespace hemivem
