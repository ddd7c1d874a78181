// Overrides of arrays of tables: "key[+]={...}" appends one table, "key=[...]" replaces the
// whole array and says so in the scene's warnings; nothing is dropped without a word.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <hemivem/error.hpp>
#include <hemivem/scene/scene.hpp>

#include "test_support.hpp"

namespace hemivem {
namespace {

// a roller on the left and a pinned bottom, one traction, one contact part, one region
const char* const kScene = R"(schema_version = 1
title = "rollers"
[mesh]
generator = "squares"
n = 4
[material]
E = 1.0
nu = 0.3
[[material.region]]
id = 1
E = 2.0
nu = 0.3
box = [0.0, 0.5, 0.0, 0.5]
[[dirichlet]]
side = "left"
ux = 0.0
[[loads.traction]]
side = "top"
value = [0.0, -1.0]
[contact]
side = "bottom"
law = "paper"
)";

Scene written() { return parse_scene_string(kScene, "rollers.toml"); }

std::vector<std::string> sides(const BoundarySelector& b) { return b.sides; }

TEST(SceneOverrides, AppendAddsOneTableAndKeepsTheScenesOwn) {
  Scene s = written();
  apply_overrides(s, {"dirichlet[+]={side=\"right\", uy=0}", "loads.traction[+]={side=\"right\", value=[1, 0]}",
                      "material.region[+]={id=2, E=3.0, nu=0.25, box=[0.5, 1.0, 0.5, 1.0]}",
                      "contact[+]={side=\"top\", law=\"paper\"}"});
  ASSERT_EQ(s.dirichlet.size(), 2u);
  EXPECT_EQ(s.dirichlet[0], written().dirichlet[0]);  // the file's roller, unchanged
  EXPECT_EQ(sides(s.dirichlet[1].boundary), std::vector<std::string>{"right"});
  EXPECT_FALSE(s.dirichlet[1].ux.has_value());
  ASSERT_TRUE(s.dirichlet[1].uy.has_value());
  ASSERT_EQ(s.tractions.size(), 2u);
  EXPECT_EQ(s.tractions[0], written().tractions[0]);
  EXPECT_EQ(s.tractions[1].value[0].value, 1.0);
  ASSERT_EQ(s.material.regions.size(), 2u);
  EXPECT_EQ(s.material.regions[1].region, 2);
  EXPECT_EQ(s.material.regions[1].young, 3.0);
  ASSERT_EQ(contact_parts(s).size(), 2u);  // the single [contact] is the first of two
  EXPECT_EQ(sides(contact_parts(s)[0].boundary), std::vector<std::string>{"bottom"});
  EXPECT_EQ(sides(contact_parts(s)[1].boundary), std::vector<std::string>{"top"});
  EXPECT_EQ(s.override_notices, std::vector<std::string>{});  // nothing was dropped
}

TEST(SceneOverrides, AppendToAnArrayTheSceneDoesNotHaveMakesIt) {
  Scene s = written();
  apply_override(s, "dirichlet=");  // no [[dirichlet]] left
  EXPECT_TRUE(s.dirichlet.empty());
  apply_override(s, "dirichlet[+]={side=\"left\", ux=0}");
  ASSERT_EQ(s.dirichlet.size(), 1u);
  EXPECT_EQ(s.dirichlet[0], written().dirichlet[0]);
}

TEST(SceneOverrides, ReplacingAnArrayIsAllowedAndReported) {
  Scene s = written();
  apply_override(s, "dirichlet=[{side=\"right\", ux=0}, {side=\"right\", uy=0}]");
  ASSERT_EQ(s.dirichlet.size(), 2u);
  EXPECT_EQ(sides(s.dirichlet[0].boundary), std::vector<std::string>{"right"});
  const std::vector<std::string> expected{
      "--set dirichlet replaced the whole array [[dirichlet]]: its 1 table by 2 (to add one table instead: --set "
      "'dirichlet[+]={...}')"};
  EXPECT_EQ(s.override_notices, expected);
  const auto w = scene_warnings(s);
  EXPECT_NE(std::find(w.begin(), w.end(), expected[0]), w.end());
  // a later override keeps the notice; removing a whole array is reported too
  apply_override(s, "loads.traction=");
  ASSERT_EQ(s.override_notices.size(), 2u);
  EXPECT_EQ(s.override_notices[1], "--set loads.traction removed [[loads.traction]] with its 1 table");
  EXPECT_TRUE(s.tractions.empty());
}

TEST(SceneOverrides, SettingAKeyOfOneTableIsNoReplacement) {
  Scene s = written();
  apply_overrides(s, {"dirichlet[0].ux=0.5", "contact.gap=0.01", "mesh.n=8"});
  EXPECT_TRUE(s.override_notices.empty());
  EXPECT_TRUE(scene_warnings(s).empty());
}

TEST(SceneOverrides, AnIndexPastTheEndPointsAtTheAppendForm) {
  Scene s = written();
  const std::string m = test::input_error_of([&] { apply_override(s, "dirichlet[1].uy=0"); });
  EXPECT_NE(m.find("no element 1 in 'dirichlet' (1 table(s)); 'dirichlet[+]={...}' appends one"), std::string::npos) << m;
  EXPECT_NE(test::input_error_of([&] { apply_override(s, "dirichlet[+]=3"); }).find("appends one table"),
            std::string::npos);
  EXPECT_NE(test::input_error_of([&] { apply_override(s, "dirichlet[+].ux=3"); }).find("ends the key"),
            std::string::npos);
  EXPECT_NE(test::input_error_of([&] { apply_override(s, "dirichlet[x].ux=3"); }).find("bad index"),
            std::string::npos);
  EXPECT_EQ(s, written());  // refused overrides change nothing
}

}  // namespace
}  // namespace hemivem
