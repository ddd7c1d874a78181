// Friction in scenes and in the command's outputs (docs/friction.md, docs/reference/scenes.md): the
// [contact.friction] table and the bilateral constraint as read, written and refused; the
// columns, fields and pictures a frictional solve writes, checked against each other and
// against the reduced problem's file form.
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/scene/scene.hpp>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace hemivem;

namespace {

using test::CommandRun;
using test::scratch;
using test::scenes_dir;
using test::slurp;

const std::string kContact = "schema_version = 1\n[contact]\nside = \"bottom\"\n";

std::string scene_error(const std::string& text) {
  return test::input_error_of([&] { (void)parse_scene_string(text, "friction.toml"); });
}

TEST(FrictionScene, ShippedScenesPoseTheirLawsAndRoundTrip) {
  const Scene tresca = parse_scene(scenes_dir() / "friction-tresca.toml");
  ASSERT_TRUE(tresca.contact && tresca.contact->friction);
  EXPECT_EQ(tresca.contact->friction->name, "tresca");
  EXPECT_EQ(tresca.contact->friction->parameters.at("bound"), 1.5);
  const Scene weakening = parse_scene(scenes_dir() / "friction-slip-weakening.toml");
  ASSERT_TRUE(weakening.contact && weakening.contact->friction);
  EXPECT_EQ(weakening.contact->friction->name, "slip-weakening");
  for (const Scene* s : {&tresca, &weakening}) EXPECT_EQ(parse_scene_string(to_toml(*s), "again.toml"), *s);
  // the law built is the one of the library, with the scene's parameters
  const auto built = build_problem(weakening);
  ASSERT_TRUE(built->problem.parts[0].friction);
  const auto reference = slip_weakening_law(1.5, 0.5, 1e-3);
  for (double r : {-0.01, -5e-4, 0.0, 2e-4, 1e-3, 0.02})
    EXPECT_EQ(built->problem.parts[0].friction->value(LawPart::j, r), reference->value(LawPart::j, r)) << r;
}

TEST(FrictionScene, DefaultsBilateralPiecewiseAndOverrides) {
  Scene s = parse_scene_string(kContact + "constraint = \"bilateral\"\n[contact.friction]\n", "f.toml");
  EXPECT_EQ(s.contact->constraint, ConstraintKind::bilateral);
  EXPECT_EQ(s.contact->friction->name, "tresca");  // the default law, bound 0.1
  EXPECT_EQ(build_problem(s)->problem.parts[0].friction->value(LawPart::j, -2.0), 0.2);
  apply_override(s, "contact.friction.bound=0.7");
  EXPECT_EQ(s.contact->friction->parameters.at("bound"), 0.7);
  // switching the law leaves the old law's key behind: named, with the keys the new law has
  const std::string stale = test::input_error_of([&] { apply_override(s, "contact.friction.law=slip-weakening"); });
  EXPECT_NE(stale.find("'bound' is a parameter of friction law 'tresca', not of 'slip-weakening' (which has: static, "
                       "kinetic, distance)"),
            std::string::npos)
      << stale;
  Scene w = parse_scene_string(kContact, "w.toml");
  apply_overrides(w, {"contact.friction.static=0.3", "contact.friction.law=slip-weakening"});
  EXPECT_EQ(w.contact->friction->name, "slip-weakening");
  EXPECT_EQ(w.contact->friction->parameters.at("static"), 0.3);
  // an even piecewise law: Tresca written by hand
  const Scene p = parse_scene_string(kContact + "[contact.friction]\nlaw = \"piecewise\"\nbreakpoints = [0.0]\n"
                                                "j1 = [[0.0, -0.3], [0.0, 0.3]]\nj2 = [[0.0], [0.0]]\n",
                                     "p.toml");
  EXPECT_EQ(build_problem(p)->problem.parts[0].friction->value(LawPart::j, -1.0), 0.3);
  EXPECT_EQ(parse_scene_string(to_toml(p), "again.toml"), p);
}

TEST(FrictionScene, DefectsNameTheKeyAndWhatWasExpected) {
  const std::string friction = kContact + "[contact.friction]\n";
  const std::string typo = scene_error(friction + "law = \"trasca\"\n");
  EXPECT_NE(typo.find("friction.toml:5"), std::string::npos) << typo;
  EXPECT_NE(typo.find("did you mean 'tresca'?"), std::string::npos) << typo;
  const std::string other = scene_error(friction + "law = \"tresca\"\nstatic = 0.2\n");
  EXPECT_NE(other.find("friction.toml:6"), std::string::npos) << other;
  EXPECT_NE(other.find("'static' is a parameter of friction law 'slip-weakening', not of 'tresca'"), std::string::npos)
      << other;
  const std::string range = scene_error(friction + "law = \"slip-weakening\"\nstatic = 0.1\nkinetic = 0.3\n");
  EXPECT_NE(range.find("kinetic <= static"), std::string::npos) << range;
  EXPECT_NE(scene_error(friction + "bound = -1\n").find("must be finite and >= 0"), std::string::npos);
  const std::string odd = scene_error(friction + "law = \"piecewise\"\nbreakpoints = [0.0]\n"
                                                 "j1 = [[0.0, -0.3], [0.0, 0.5]]\nj2 = [[0.0], [0.0]]\n");
  EXPECT_NE(odd.find("must be even"), std::string::npos) << odd;
  const std::string obstacle = scene_error(kContact + "constraint = \"bilateral\"\n[contact.obstacle]\nshape = \"plane\"\n"
                                                      "point = [0.0, 0.0]\nnormal = [0.0, 1.0]\n");
  EXPECT_NE(obstacle.find("takes no [contact.obstacle]"), std::string::npos) << obstacle;
  EXPECT_NE(scene_error(friction + "bond = 1\n").find("unknown key 'bond'"), std::string::npos);
  const std::string unknown = scene_error(kContact + "constraint = \"sliding\"\n");
  EXPECT_NE(unknown.find("none, one-sided, box, bilateral"), std::string::npos) << unknown;
}

/// The rows of a CSV file by column name.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  for (std::stringstream ss(line); std::getline(ss, line, ',');) header.push_back(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::stringstream ss(line);
    for (const auto& h : header) std::getline(ss, row[h], ',');
    rows.push_back(row);
  }
  return rows;
}

TEST(FrictionCli, SolveWritesTheTangentialDisplacementForcesAndStates) {
  const fs::path out = scratch("friction-solve"), reduced = scratch("friction-reduced-cli");
  const CommandRun r = test::run_hemivem("solve " + (scenes_dir() / "friction-tresca.toml").string() +
                                         " --n 16 --out " + out.string() + " --export-reduced " + reduced.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("friction      tresca: "), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  EXPECT_EQ(j.at("schema"), "hemivem-result/26");
  EXPECT_EQ(j.at("friction").at("law"), "tresca");
  const auto rows = read_csv(out / "contact.csv");
  ASSERT_EQ(rows.size(), j.at("contact").size());
  int stick = 0, slip = 0;
  double tangential = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& node = j.at("contact")[i];
    const std::string state = node.at("friction_state");
    EXPECT_EQ(rows[i].at("friction_state"), state);
    EXPECT_EQ(std::stod(rows[i].at("u_tau")), node.at("u_tau").get<double>());
    const double force = node.at("friction_force"), u_tau = node.at("u_tau");
    // stick: u_tau = 0 and |force| within the bound; slip: the force at the bound against u_tau
    const double bound = 1.5 * node.at("friction_force").get<double>() / node.at("friction_traction").get<double>();
    if (state == "stick") {
      ++stick;
      EXPECT_EQ(u_tau, 0.0);
      EXPECT_LE(std::abs(force), std::abs(bound) * (1.0 + 1e-9));
    } else {
      ++slip;
      EXPECT_EQ(state, "slip");
      EXPECT_NE(u_tau, 0.0);
      EXPECT_NEAR(node.at("friction_traction").get<double>(), u_tau > 0 ? 1.5 : -1.5, 1e-9);
    }
    tangential += force;  // tau = (1, 0) on the bottom: the force on the body is -force along x
  }
  EXPECT_GT(stick, 0);
  EXPECT_GT(slip, 0);
  EXPECT_EQ(j.at("friction").at("nodes").at("stick"), stick);
  EXPECT_EQ(j.at("friction").at("nodes").at("slip"), slip);
  EXPECT_NEAR(j.at("contact_force")[0].get<double>(), -tangential, 1e-12);
  const std::string vtu = slurp(out / "solution.vtu");
  for (const char* name : {"u_tau", "friction_traction", "friction_state"})
    EXPECT_NE(vtu.find("Name=\"" + std::string(name) + "\""), std::string::npos) << name;
  EXPECT_TRUE(fs::exists(out / "u_nu.png"));
  // the reduced problem's file form reaches the same tangential displacements
  const CommandRun m = test::run_hemivem("minimize " + reduced.string() + " --json");
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  const auto mj = nlohmann::json::parse(m.out);
  EXPECT_EQ(mj.at("constraint"), "coordinate-wise");
  EXPECT_EQ(mj.at("laws"), nlohmann::json({"paper", "tresca"}));
  const std::size_t n = rows.size();
  ASSERT_EQ(mj.at("a").size(), 2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(mj.at("a")[i].get<double>(), j.at("contact")[i].at("u_nu").get<double>(), 1e-12);
    EXPECT_NEAR(mj.at("a")[n + i].get<double>(), j.at("contact")[i].at("u_tau").get<double>(), 1e-12);
  }
}

// Slip-weakening on a coarse mesh: a negative margin, every result marked possibly non-unique,
// and check reports the engines' distinct critical points without failing.
TEST(FrictionCli, CheckOnSlipWeakeningAcceptsDistinctCriticalPoints) {
  const CommandRun r =
      test::run_hemivem("check " + (scenes_dir() / "friction-slip-weakening.toml").string() + " --n 16 --json");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("unique"), false);
  EXPECT_LT(j.at("uniqueness_margin").get<double>(), 0.0);
  EXPECT_TRUE(j.at("agree_ok").get<bool>());
  for (const auto& p : j.at("pairs")) EXPECT_TRUE(p.at("converged").get<bool>()) << p.at("linear") << "+" << p.at("minimizer");
  if (j.at("max_difference").get<double>() > j.at("agree").get<double>())
    EXPECT_NE(j.at("verdict").get<std::string>().find("not a disagreement"), std::string::npos) << j.at("verdict");
  const fs::path out = scratch("friction-nonunique");
  const CommandRun s = test::run_hemivem("solve " + (scenes_dir() / "friction-slip-weakening.toml").string() +
                                         " --n 16 --out " + out.string() + " --json");
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(nlohmann::json::parse(s.out).at("may_be_nonunique"), true);
}

TEST(FrictionCli, FrictionlessResultsSayNoFriction) {
  const fs::path out = scratch("frictionless");
  const CommandRun r = test::run_hemivem("solve --n 8 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  EXPECT_TRUE(j.at("friction").is_null());
  EXPECT_FALSE(j.at("contact")[0].contains("u_tau"));
  EXPECT_EQ(slurp(out / "contact.csv").find("u_tau"), std::string::npos);
}

// Coulomb's law is solved as Tresca problems of bound mu p set by a fixed point; every output
// names the model the scene poses, with what sets its bound.
TEST(FrictionCli, CoulombIsNamedCoulombWithItsCoefficient) {
  const fs::path scene = scenes_dir() / "friction-coulomb.toml";
  const Scene written = parse_scene(scene);
  ASSERT_EQ(written.contact->friction->name, "coulomb");
  const double mu = written.contact->friction->parameters.at("coefficient");
  const fs::path out = scratch("friction-coulomb-named");
  const CommandRun r = test::run_hemivem("solve " + scene.string() + " --n 8 --set 'path.t=[1.0, 2.0]' --out " +
                                         out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  std::ostringstream line;
  line << "friction      coulomb (mu = " << mu << "): ";
  EXPECT_NE(r.out.find(line.str()), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("tresca"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  EXPECT_EQ(j.at("friction").at("law"), "coulomb");
  const nlohmann::json models = nlohmann::json::array(
      {{{"part", contact_part_name(written, 0)}, {"law", "coulomb"}, {"coefficient", mu}}});
  EXPECT_EQ(j.at("friction").at("models"), models);
  EXPECT_EQ(slurp(out / "result.json").find("tresca"), std::string::npos);
  fs::remove_all(out);
}

TEST(FrictionCli, ATrescaBoundTableIsNamedAsSuch) {
  const fs::path out = scratch("friction-table-named");
  const CommandRun r = test::run_hemivem(
      "solve " + (scenes_dir() / "friction-coulomb.toml").string() +
      " --n 8 --set 'path.t=[1.0, 2.0]' --set contact.friction.law=tresca --set contact.friction.coefficient= "
      "--set 'contact.friction.bound=[[0, 1.5], [0.01, 0.5]]' --out " +
      out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("friction      tresca (bound table h(u_nu) of 2 points): "), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  EXPECT_EQ(j.at("friction").at("law"), "tresca");
  const nlohmann::json models = nlohmann::json::array(
      {{{"part", "contact"}, {"law", "tresca"}, {"bound_table", {{0.0, 1.5}, {0.01, 0.5}}}}});
  EXPECT_EQ(j.at("friction").at("models"), models);
  fs::remove_all(out);
}

}  // namespace
