// hemivem check --extreme and the memory refusal, through the built binary.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>

#include <hemivem/krylov_solver.hpp>

#include "test_support.hpp"

namespace hemivem {
namespace {

// Every pair, the full-space route's (each Krylov engine with ssn) among them: the condensed
// pairs estimate the condition of their factorized matrix, the full-space pairs factorize
// nothing and have none; every converged pair keeps its guarantee (its certificate
// recomputed: from the reduced problem, or from the posed whole system) and all agree.
TEST(CliExtreme, ReportsEveryPairWithItsGuaranteeAsJson) {
  const auto run = test::run_hemivem("check --extreme --only gap-zero,lift-off --json");
  ASSERT_EQ(run.code, 0) << run.err;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["schema"], "hemivem-stability/2");
  EXPECT_TRUE(j["guarantees_ok"].get<bool>());
  ASSERT_EQ(j["scenes"].size(), 2u);
  for (const auto& s : j["scenes"]) {
    ASSERT_FALSE(s["pairs"].empty());
    EXPECT_TRUE(s["unique"].get<bool>()) << s["name"];
    EXPECT_LT(s["max_difference"].get<double>(), 1e-6) << s["name"];
    std::size_t full_space = 0;
    for (const auto& p : s["pairs"]) {
      EXPECT_TRUE(p["converged"].get<bool>()) << s["name"] << " " << p["linear"] << "+" << p["minimizer"];
      EXPECT_TRUE(p["guarantee_ok"].get<bool>());
      EXPECT_LT(p["max_difference"].get<double>(), 1e-6) << s["name"] << " " << p["linear"];
      if (p["route"] == "full_space") {
        ++full_space;
        EXPECT_EQ(p["minimizer"], "ssn");
        EXPECT_TRUE(p["condition_estimate"].is_null()) << p["linear"];
        EXPECT_TRUE(p["uniqueness_margin"].is_null()) << p["linear"];
      } else {
        EXPECT_GT(p["condition_estimate"].get<double>(), 1.0);
      }
      const int bound = p["at_bound"].get<int>();
      EXPECT_EQ(bound, s["name"] == "gap-zero" ? s["contact_nodes"].get<int>() : 0) << s["name"];
    }
    EXPECT_EQ(full_space, hemivem::available_krylov_solvers().size()) << s["name"];
  }
}

// The three-dimensional extreme scenes: a thin plate, a near-penalty law and a grazing sphere,
// where one node (on the axis) touches. Every pair keeps its guarantee and the converged pairs
// agree; on the plate and the sphere every pair converges, on the near-penalty law ssn does with
// every linear engine (bundle-dca may stall there just above the tolerance, and says so).
TEST(CliExtreme, ThreeDimensionalScenesConvergeAndAgree) {
  const auto run = test::run_hemivem("check --extreme --only plate-3d-thin,stiff-law-3d,grazing-sphere-3d --json");
  ASSERT_EQ(run.code, 0) << run.err;
  const auto j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j["scenes"].size(), 3u);
  for (const auto& s : j["scenes"]) {
    ASSERT_FALSE(s["pairs"].empty()) << s["name"];
    EXPECT_LT(s["max_difference"].get<double>(), 1e-6) << s["name"];
    for (const auto& p : s["pairs"]) {
      if (s["name"] != "stiff-law-3d" || p["minimizer"] == "ssn")
        EXPECT_TRUE(p["converged"].get<bool>()) << s["name"] << " " << p["linear"] << "+" << p["minimizer"];
      EXPECT_TRUE(p["guarantee_ok"].get<bool>()) << s["name"];
      if (s["name"] == "grazing-sphere-3d" && p["converged"].get<bool>()) EXPECT_EQ(p["at_bound"].get<int>(), 1);
    }
    if (s["name"] == "grazing-sphere-3d") EXPECT_TRUE(s["unique"].get<bool>());
  }
}

// A friction bound 10^6 times the load sticks every contact node, a bound of 0 none; every
// pair converges to the same point.
TEST(CliExtreme, FrictionBoundsStickEverythingOrNothing) {
  const auto run = test::run_hemivem("check --extreme --only friction-stick,friction-slip --json");
  ASSERT_EQ(run.code, 0) << run.err;
  const auto j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j["scenes"].size(), 2u);
  for (const auto& s : j["scenes"]) {
    EXPECT_TRUE(s["unique"].get<bool>()) << s["name"];
    EXPECT_LT(s["max_difference"].get<double>(), 1e-6) << s["name"];
    const int nodes = s["contact_nodes"].get<int>();
    ASSERT_GT(nodes, 0);
    for (const auto& p : s["pairs"]) {
      EXPECT_TRUE(p["converged"].get<bool>()) << s["name"] << " " << p["linear"] << "+" << p["minimizer"];
      EXPECT_EQ(p["stick"].get<int>(), s["name"] == "friction-stick" ? nodes : 0) << s["name"];
    }
  }
}

TEST(CliExtreme, TableAndClearErrors) {
  const auto table = test::run_hemivem("check --extreme --only polyline-contact");
  EXPECT_EQ(table.code, 0) << table.err;
  EXPECT_NE(table.out.find("polyline-contact"), std::string::npos);
  EXPECT_NE(table.out.find("kappa_1"), std::string::npos);
  EXPECT_NE(table.out.find("no guarantee broken"), std::string::npos) << table.out;

  const auto unknown = test::run_hemivem("check --extreme --only no-such-scene");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("--only"), std::string::npos) << unknown.err;
  EXPECT_NE(unknown.err.find("nu-0.4999"), std::string::npos) << "lists the scenes: " << unknown.err;

  const auto mixed = test::run_hemivem("check --extreme --n 8");
  EXPECT_EQ(mixed.code, 2) << mixed.err;
}

TEST(CliExtreme, RefusesARequestThatCannotFitBeforeAllocating) {
  const auto out = test::scratch("memory-refusal");
  const auto run = test::run_hemivem("solve --n 1000000 --out " + out.string());
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.err.find("needs an estimated"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("available"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(out)) << "no output folder for a refused request";

  setenv("HEMIVEM_MEMORY_LIMIT", "16M", 1);
  const auto limited = test::run_hemivem("solve --n 128 --out " + out.string());
  unsetenv("HEMIVEM_MEMORY_LIMIT");
  EXPECT_EQ(limited.code, 2);
  EXPECT_NE(limited.err.find("more than the 16 MiB available (HEMIVEM_MEMORY_LIMIT)"), std::string::npos) << limited.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace hemivem
