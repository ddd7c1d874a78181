// End-to-end tests of hemivem check and hemivem bench: they run the built binary.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>
#include <sys/wait.h>

#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

#include "bench.hpp"
#include "engine_pairs.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using hemivem::test::CommandRun;
using hemivem::test::scratch;
using hemivem::test::slurp;
CommandRun run(const std::string& args) { return hemivem::test::run_hemivem(args); }


std::vector<std::string> split(const std::string& line, char sep = ',') {
  std::vector<std::string> parts;
  std::stringstream ss(line);
  std::string part;
  while (std::getline(ss, part, sep)) parts.push_back(part);
  if (!line.empty() && line.back() == sep) parts.emplace_back();
  return parts;
}

}  // namespace

TEST(CliCheck, EveryPairConvergesAndAgrees) {
  const CommandRun r = run("check --n 8 --json");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["schema"], "hemivem-check/5");
  ASSERT_GE(j["pairs"].size(), 1u);
  bool reference = false;
  std::vector<std::string> full_space;  // the Krylov engines of the full-space route's pairs
  for (const auto& p : j["pairs"]) {
    EXPECT_EQ(p["converged"], true) << p["linear"] << "+" << p["minimizer"];
    ASSERT_TRUE(p["max_difference"].is_number()) << p["linear"] << "+" << p["minimizer"];
    EXPECT_LT(p["max_difference"].get<double>(), 1e-6) << p["linear"] << "+" << p["minimizer"];
    reference |= p["linear"] == "eigen" && p["minimizer"] == "ssn";
    if (p["route"] == "full_space") {
      EXPECT_EQ(p["minimizer"], "ssn") << p["linear"];
      full_space.push_back(p["linear"]);
    } else {
      EXPECT_EQ(p["route"], "condensed") << p["linear"];
    }
  }
  EXPECT_TRUE(reference);
  EXPECT_EQ(full_space, hemivem::available_krylov_solvers()) << "every Krylov engine built is checked, with ssn";
  EXPECT_TRUE(j["refused"].empty()) << j["refused"];
  EXPECT_LT(j["max_difference"].get<double>(), 1e-6);
  EXPECT_EQ(j["differences"].size(), j["pairs"].size());
  EXPECT_EQ(j["agree_ok"], true);
  EXPECT_EQ(j["exit_code"], 0);
  // a unique problem's verdict is the agreement alone
  const std::string verdict = j["verdict"].get<std::string>();
  EXPECT_EQ(verdict.rfind("all ", 0), 0u) << verdict;
  EXPECT_EQ(verdict.find("pairs differ"), std::string::npos) << verdict;
  EXPECT_EQ(verdict.find("lowest energy"), std::string::npos) << verdict;
}

// A block held vertically by its contact alone: every Krylov pair solves it as the condensed pairs
// do, and the check passes with none refused.
TEST(CliCheck, ABodyHeldByItsContactAloneIsCheckedOnBothRoutes) {
  const std::string scene = (hemivem::test::scenes_dir() / "block-between-rollers.toml").string();
  const CommandRun r = run("check " + scene + " --set 'mesh.n=[8, 2]' --json -q");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  int full_space = 0;
  for (std::size_t i = 0; i < j["pairs"].size(); ++i) {
    const auto& p = j["pairs"][i];
    SCOPED_TRACE(p["linear"].get<std::string>() + "+" + p["minimizer"].get<std::string>());
    EXPECT_EQ(p["converged"], true) << p["message"];
    EXPECT_LT(p["max_difference"].get<double>(), 1e-6);
    full_space += p["route"] == "full_space" ? 1 : 0;
  }
  EXPECT_EQ(full_space, static_cast<int>(hemivem::available_krylov_solvers().size()));
  EXPECT_TRUE(j["refused"].empty());
  EXPECT_EQ(j["exit_code"], 0);
  EXPECT_EQ(j["agree_ok"], true);
}

TEST(CliCheck, DisagreementBeyondAgreeExitsSix) {
  const CommandRun r = run("check --n 8 --agree 1e-30 --json");
  EXPECT_EQ(r.code, 6) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["agree_ok"], false);
  EXPECT_EQ(j["unique"], true);
  EXPECT_GT(j["uniqueness_margin"].get<double>(), 0.0);
  EXPECT_EQ(j["exit_code"], 6);
  // the terminal table says so too
  const CommandRun t = run("check --n 8 --agree 1e-30");
  EXPECT_EQ(t.code, 6);
  EXPECT_NE(t.out.find("verdict"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("eigen"), std::string::npos) << t.out;
}

// The saw-tooth law has a concave kink (alpha_j = inf, margin -inf): distinct critical
// points are legitimate, so converged pairs that differ by more than --agree are reported
// but are not a disagreement.
TEST(CliCheck, DifferencesOnAPossiblyNonuniqueSceneAreNotADisagreement) {
  const std::string scene = (hemivem::test::scenes_dir() / "extreme" / "jump-law.toml").string();
  const CommandRun r = run("check " + scene + " --n 8 --agree 1e-30 --json -q");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["unique"], false);
  EXPECT_TRUE(j["uniqueness_margin"].is_null()) << j["uniqueness_margin"];  // -inf
  ASSERT_GE(j["pairs"].size(), 2u);
  for (const auto& p : j["pairs"]) EXPECT_EQ(p["converged"], true) << p["linear"] << "+" << p["minimizer"];
  EXPECT_GT(j["max_difference"].get<double>(), 1e-30);
  EXPECT_EQ(j["agree_ok"], true);
  EXPECT_EQ(j["exit_code"], 0);
  EXPECT_NE(j["verdict"].get<std::string>().find("not a disagreement"), std::string::npos) << j["verdict"];
  // The table says why.
  const CommandRun t = run("check " + scene + " --n 8 --agree 1e-30");
  EXPECT_EQ(t.code, 0) << t.out << t.err;
  EXPECT_NE(t.out.find("uniqueness margin lambda_min(S - alpha_j W) = -inf is not positive"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("not a disagreement"), std::string::npos) << t.out;
}

TEST(CliCheck, BenchWritesOneRowPerPairAndSizeAndSsnErrorsDecrease) {
  const fs::path out = scratch("bench");
  const CommandRun r = run("bench --n 4,8 --ref 16 --out " + out.string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;  // -q
  const auto j = nlohmann::json::parse(slurp(out / "bench.json"));
  EXPECT_EQ(j["schema"], "hemivem-bench/6");
  EXPECT_EQ(j["dimension"], 2);
  EXPECT_EQ(j["reference"]["n"], 16);

  std::ifstream csv(out / "bench.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const auto header = split(line);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* c : {"linear", "minimizer", "n", "mesh", "assembly", "condensation", "minimize",
                        "back_substitution", "total", "error"})
    ASSERT_TRUE(col.count(c)) << c;

  std::map<std::string, std::map<int, double>> error;  // pair -> n -> error
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    if (line.empty()) continue;
    const auto f = split(line);
    ASSERT_EQ(f.size(), header.size()) << line;
    const std::string pair = f[col["linear"]] + "+" + f[col["minimizer"]];
    const int n = std::stoi(f[col["n"]]);
    EXPECT_FALSE(error[pair].count(n)) << "duplicate row " << line;
    ASSERT_FALSE(f[col["error"]].empty()) << line;
    error[pair][n] = std::stod(f[col["error"]]);
    EXPECT_GE(std::stod(f[col["total"]]), std::stod(f[col["minimize"]])) << line;
    ++rows;
  }
  ASSERT_EQ(rows, 2 * error.size());
  EXPECT_EQ(j["rows"].size(), rows);
  // the full-space route's pairs are timed like the others, by their own stages
  for (const char* c : {"posing", "full_space"}) ASSERT_TRUE(col.count(c)) << c;
  for (const auto& k : hemivem::available_krylov_solvers()) EXPECT_TRUE(error.count(k + "+ssn")) << k;
  for (const auto& row : j["rows"]) {
    const bool full_space = row["route"] == "full_space";
    EXPECT_EQ(full_space, hemivem::is_krylov_solver(row["linear"].get<std::string>())) << row["linear"];
    const auto& t = row["seconds"];
    if (!full_space) continue;
    EXPECT_EQ(row["converged"], true) << row["linear"];
    EXPECT_GT(t["posing"].get<double>(), 0.0) << row["linear"];
    EXPECT_GT(t["full_space"].get<double>(), 0.0) << row["linear"];
    EXPECT_EQ(t["condensation"].get<double>(), 0.0) << row["linear"];
    EXPECT_GE(t["total"].get<double>(), t["posing"].get<double>() + t["full_space"].get<double>()) << row["linear"];
  }
  // one row per pair and size: the pairs check reports
  const auto check = nlohmann::json::parse(run("check --n 4 --json -q").out);
  EXPECT_EQ(error.size(), check["pairs"].size());
  int ssn = 0;
  for (const auto& [pair, by_n] : error) {
    ASSERT_EQ(by_n.size(), 2u) << pair;
    if (!pair.ends_with("+ssn")) continue;
    ++ssn;
    EXPECT_LT(by_n.at(8), by_n.at(4)) << pair;
    EXPECT_GT(by_n.at(4), 0.0) << pair;
  }
  EXPECT_GE(ssn, 1);
  fs::remove_all(out);
}

// Aitken's delta-squared on a geometric sequence gives its limit exactly; sequences that do not
// decay geometrically in one direction have no reference.
TEST(BenchAitken, ExtrapolatesAGeometricSequenceAndRefusesOthers) {
  // Phi_k = -1 + 0.3 * 0.25^k: limit -1
  const auto ref = hemivem::cli::aitken_reference(-1 + 0.3, -1 + 0.3 * 0.25, -1 + 0.3 * 0.0625);
  ASSERT_TRUE(ref.has_value());
  EXPECT_NEAR(*ref, -1.0, 1e-14);
  // from below as well
  const auto up = hemivem::cli::aitken_reference(2 - 0.5, 2 - 0.25, 2 - 0.125);
  ASSERT_TRUE(up.has_value());
  EXPECT_NEAR(*up, 2.0, 1e-14);
  EXPECT_FALSE(hemivem::cli::aitken_reference(1.0, 0.5, 0.6).has_value());   // the differences change sign
  EXPECT_FALSE(hemivem::cli::aitken_reference(1.0, 0.9, 0.7).has_value());   // they grow
  EXPECT_FALSE(hemivem::cli::aitken_reference(1.0, 0.5, 0.0).has_value());   // they do not decay (ratio 1)
  EXPECT_FALSE(hemivem::cli::aitken_reference(1.0, 1.0, 1.0).has_value());   // no difference
  EXPECT_FALSE(hemivem::cli::aitken_reference(1.0, 0.5, 0.5).has_value());   // the last difference is 0
}

// The refinement study runs on any mesh kind: a triangle mesh, refined uniformly and adaptively.
TEST(CliCheck, BenchRefinementStudyOnATriangleMesh) {
  const fs::path out = scratch("bench-refine");
  const std::string scene = (hemivem::test::scenes_dir() / "polygon-bracket.toml").string();
  const CommandRun r =
      run("bench " + scene + " --n 4 --ref 8 --set mesh.n=6 --levels 2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("refinement study"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("hemivem bench: uniform level 2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("hemivem bench: adaptive step 0"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "bench.json"));
  // a triangle mesh has errors against its reference (on triangles n = --ref)
  ASSERT_TRUE(j["reference"].is_object()) << j.dump(2);
  EXPECT_EQ(j["reference"]["n"], 8);
  for (const auto& row : j["rows"]) EXPECT_GT(row["error"].get<double>(), 0.0) << row;
  ASSERT_TRUE(j.contains("refinement")) << j.dump(2);
  const auto& f = j["refinement"];
  ASSERT_EQ(f["uniform"].size(), 3u);
  for (std::size_t k = 1; k < 3; ++k)
    EXPECT_GT(f["uniform"][k]["unknowns"].get<int>(), f["uniform"][k - 1]["unknowns"].get<int>());
  for (const auto& p : f["uniform"]) {
    EXPECT_GT(p["estimate"].get<double>(), 0.0);
    EXPECT_GT(p["seconds"].get<double>(), 0.0);
    EXPECT_TRUE(p["potential_energy"].is_number());
  }
  ASSERT_GE(f["adaptive"]["steps"].size(), 2u) << f.dump(2);
  EXPECT_TRUE(f["adaptive"]["stopped"].is_string());
  EXPECT_EQ(f["adaptive"]["steps"][0]["unknowns"], f["uniform"][0]["unknowns"]);
  EXPECT_LE(f["adaptive"]["steps"].back()["unknowns"].get<int>(), f["uniform"][2]["unknowns"].get<int>());
  EXPECT_TRUE(f["reference"].is_string());
  EXPECT_TRUE(f["below_reference"].is_number_integer());

  // With a reference energy every point has a true error and an effectivity.
  const double phi = f["uniform"][2]["potential_energy"].get<double>();
  const double given = phi - 2e-2 * std::abs(phi);  // well below every point of the study
  std::ostringstream arg;
  arg << std::setprecision(17) << given;
  const CommandRun g = run("bench " + scene + " --n 4 --ref 8 --set mesh.n=6 --levels 1 --reference-energy " + arg.str() +
                           " -q --out " + out.string());
  ASSERT_EQ(g.code, 0) << g.err;
  const auto k = nlohmann::json::parse(slurp(out / "bench.json"))["refinement"];
  EXPECT_DOUBLE_EQ(k["reference_energy"].get<double>(), given);
  EXPECT_EQ(k["below_reference"], 0);
  EXPECT_EQ(k["uniform"].size(), 2u);
  for (const auto* list : {&k["uniform"], &k["adaptive"]["steps"]})
    for (const auto& p : *list) {
      ASSERT_TRUE(p["error"].is_number()) << p.dump();
      EXPECT_GT(p["error"].get<double>(), 0.0);
      EXPECT_NEAR(p["effectivity"].get<double>(), p["estimate"].get<double>() / p["error"].get<double>(), 1e-12);
    }
  fs::remove_all(out);
}

TEST(CliCheck, BenchRefusesLevelsBelowOne) {
  const fs::path out = scratch("bench-levels");
  for (const char* levels : {"0", "-2"}) {
    const CommandRun r = run(std::string("bench --n 4 --ref 8 --levels ") + levels + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << levels;
    EXPECT_NE(r.err.find("--levels"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out / "bench.json"));
  fs::remove_all(out);
}

TEST(CliCheck, BenchRefusesAListWithABadEntryNamingTheFlagAndTheEntry) {
  const fs::path out = scratch("bench-list");
  const CommandRun empty = run("bench --n 4,,8 --ref 8 --levels 1 --out " + out.string());
  EXPECT_EQ(empty.code, 2) << empty.err;
  EXPECT_NE(empty.err.find("--n"), std::string::npos) << empty.err;
  EXPECT_NE(empty.err.find("entry 2 of '4,,8' is empty"), std::string::npos) << empty.err;
  const CommandRun word = run("bench --n 4,x8 --ref 8 --levels 1 --out " + out.string());
  EXPECT_EQ(word.code, 2);
  EXPECT_NE(word.err.find("'x8'"), std::string::npos) << word.err;
  for (const char* list : {"4,", ",4", "4,0"}) EXPECT_EQ(run(std::string("bench --n ") + list + " --out " + out.string()).code, 2) << list;
  const CommandRun study = run("study --n 4,,8 --ref 16 --out " + out.string());
  EXPECT_EQ(study.code, 2);
  EXPECT_NE(study.err.find("entry 2"), std::string::npos) << study.err;
  EXPECT_FALSE(fs::exists(out / "bench.json"));
  fs::remove_all(out);
}

TEST(CliCheck, CheckAndBenchRunACoulombPath) {
  const std::string scene = (hemivem::test::scenes_dir() / "friction-coulomb.toml").string();
  const std::string path = " --set 'path.t=[0.5, 1.0, 1.5]' --set mesh.n=4";
  const CommandRun c = run("check " + scene + " --n 4" + path + " --json");
  ASSERT_EQ(c.code, 0) << c.out << c.err;
  const auto j = nlohmann::json::parse(c.out);
  ASSERT_EQ(j["path"]["steps"].size(), 3u) << j.dump(2);
  EXPECT_EQ(j["path"]["compared"], "every step");
  for (const auto& step : j["path"]["steps"]) EXPECT_LT(step["max_difference"].get<double>(), 1e-6) << step;
  const CommandRun table = run("check " + scene + " --n 4" + path);
  EXPECT_NE(table.out.find("a loading path of 3 steps"), std::string::npos) << table.out;

  const fs::path out = scratch("bench-path");
  const CommandRun b = run("bench " + scene + " --n 4 --ref 8 --levels 1" + path + " -q --out " + out.string());
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(b.err.find("static problem"), std::string::npos) << b.err;
  const auto k = nlohmann::json::parse(slurp(out / "bench.json"));
  EXPECT_EQ(k["path"]["steps"], 3);
  for (const auto& row : k["rows"]) EXPECT_TRUE(row["error"].is_number()) << row;
  fs::remove_all(out);
}

TEST(CliCheck, BadInputExitsTwo) {
  EXPECT_EQ(run("check --n 0").code, 2);
  const CommandRun bad_key = run("check --n 4 --set no.such.key=1");
  EXPECT_EQ(bad_key.code, 2);
  EXPECT_NE(bad_key.err.find("no.such.key"), std::string::npos) << bad_key.err;
  EXPECT_EQ(run("check --n 4 --agree -1").code, 2);
  const fs::path out = scratch("bad");
  EXPECT_EQ(run("bench --n 0,4 --ref 8 --out " + out.string()).code, 2);
  EXPECT_EQ(run("bench --n 4 --ref 8 --set no.such.key=1 --out " + out.string()).code, 2);
  EXPECT_FALSE(fs::exists(out / "bench.csv"));
  fs::remove_all(out);
}

namespace {

TEST(CliBenchLimit, MeasuresEveryStageAndTheLimitInFreshProcesses) {
  const fs::path out = scratch("limit");
  const CommandRun r = run("bench --limit --n 16,8 --repeat 2 --out " + out.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j, nlohmann::json::parse(slurp(out / "limit.json")));
  EXPECT_EQ(j["schema"], "hemivem-bench-limit/4");
  EXPECT_EQ(j["linear"], "cholmod");
  EXPECT_EQ(j["repeat"], 2);
  ASSERT_EQ(j["rows"].size(), 2u);
  int previous = 0;
  for (const auto& row : j["rows"]) {
    const int n = row["n"];
    EXPECT_GT(n, previous);  // increasing
    previous = n;
    // Example 4.1: x = 0 and x = 1 clamped, every other dof free
    EXPECT_EQ(row["dofs"], 2 * (n + 1) * (n - 1));
    EXPECT_EQ(row["contact_nodes"], n - 1);
    EXPECT_EQ(row["status"], "converged");
    // the solve's wall time holds its stages up to result.json; margin and outputs are timed after it
    double sum = 0.0;
    for (const char* k : {"mesh", "assembly", "condensation", "minimize", "back_substitution", "result_json",
                          "margin", "outputs"}) {
      ASSERT_TRUE(row["stages"].contains(k)) << k;
      EXPECT_GE(row["stages"][k].get<double>(), 0.0) << k;
      if (std::string(k) != "margin" && std::string(k) != "outputs") sum += row["stages"][k].get<double>();
    }
    EXPECT_GT(row["stages"]["condensation"].get<double>(), 0.0);
    EXPECT_GT(row["stages"]["result_json"].get<double>(), 0.0);
    const double solve = row["solve"].get<double>();
    EXPECT_GE(solve, sum * (1.0 - 1e-12));
    const auto& limit = row["limit"];
    EXPECT_GT(limit["plain_assembly"].get<double>(), 0.0);
    EXPECT_GT(limit["factorization"].get<double>(), 0.0);
    EXPECT_TRUE(limit["ordering"] == "amd" || limit["ordering"] == "metis") << limit["ordering"];
    EXPECT_EQ(limit["other_orderings"].size(), 1u);
    // the lower triangle of A at least (values and row indices), and the factor holds more
    const double lower_entries = 0.5 * (row["dofs"].get<double>() + 1.0);
    EXPECT_GT(limit["matrix_bytes"].get<double>(), 12.0 * lower_entries);
    EXPECT_GT(limit["factor_bytes"].get<double>(), 0.0);
    const double factor = limit["analysis"].get<double>() + limit["factorization"].get<double>();
    EXPECT_NEAR(row["ratios"]["solve_over_limit"].get<double>(),
                solve / (limit["plain_assembly"].get<double>() + factor), 1e-9);
    const double outputs = row["stages"]["outputs"].get<double>();
    EXPECT_NEAR(row["ratios"]["outputs_over_total"].get<double>(),
                outputs / (solve - row["stages"]["result_json"].get<double>() + outputs), 1e-9);
    EXPECT_NEAR(row["ratios"]["condensation_over_factorization"].get<double>(),
                row["stages"]["condensation"].get<double>() / factor, 1e-9);
    EXPECT_GT(row["peak_rss_bytes"].get<double>(), limit["matrix_bytes"].get<double>());
  }
  fs::remove_all(out);
}

TEST(CliBenchLimit, MeasuresASolidAgainstItsPlainAssemblyOfBoxes) {
  const fs::path out = scratch("limit3d");
  const std::string scene = (hemivem::test::scenes_dir() / "example-4.1-3d.toml").string();
  const CommandRun r = run("bench --limit " + scene + " --set 'mesh.domain=[0,1,0,1,0,1]' --n 6,4 --out " +
                           out.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["rows"].size(), 2u);
  for (const auto& row : j["rows"]) {
    const int n = row["n"];
    // n^3 boxes, x = 0 and x = 1 clamped: 3 (n + 1)^2 (n - 1) dofs; the bottom's nodes off them
    EXPECT_EQ(row["dofs"], 3 * (n + 1) * (n + 1) * (n - 1));
    EXPECT_EQ(row["contact_nodes"], (n + 1) * (n - 1));
    EXPECT_EQ(row["status"], "converged");
    EXPECT_GT(row["limit"]["plain_assembly"].get<double>(), 0.0);
    EXPECT_GT(row["limit"]["factorization"].get<double>(), 0.0);
    EXPECT_GT(row["ratios"]["solve_over_limit"].get<double>(), 0.0);
  }
  const CommandRun tets = run("bench --limit " + scene + " --set mesh.generator=\"tetrahedra\" --n 4 --out " + out.string());
  EXPECT_EQ(tets.code, 2);
  EXPECT_NE(tets.err.find("cubes"), std::string::npos) << tets.err;
  fs::remove_all(out);
}

TEST(CliBenchLimit, NeedsSquaresAndLeavesNothingOnBadInput) {
  const fs::path out = scratch("limit-bad");
  const CommandRun voronoi = run("bench --limit --n 8 --set mesh.generator=\"voronoi\" --out " + out.string());
  EXPECT_EQ(voronoi.code, 2);
  EXPECT_NE(voronoi.err.find("mesh.generator"), std::string::npos) << voronoi.err;
  EXPECT_NE(voronoi.err.find("squares"), std::string::npos) << voronoi.err;
  EXPECT_EQ(run("bench --limit --n 0 --out " + out.string()).code, 2);
  EXPECT_EQ(run("bench --limit --n 8 --repeat 0 --out " + out.string()).code, 2);
  EXPECT_EQ(run("bench --n 8 --repeat 2 --out " + out.string()).code, 2);  // --repeat needs --limit
  EXPECT_FALSE(fs::exists(out / "limit.json"));
  fs::remove_all(out);
}

}  // namespace

// The runner of check, bench and check --extreme shares what the pairs have in common: one
// mesh, one assembly, one condensation per linear engine that factorizes; each pair is charged
// those shared stages as if it had run alone. A full-space pair (a Krylov engine with ssn) has
// nothing to share but the mesh: its solver assembles and poses the problem itself, and it is
// charged its own stages.
TEST(EnginePairs, OneAssemblyAndOneCondensationPerLinearEngine) {
  hemivem::Scene scene = hemivem::default_scene();
  hemivem::apply_overrides(scene, {"mesh.n=8"});
  const auto pairs = hemivem::cli::available_pairs();
  std::vector<std::string> engines;
  int full_space = 0;
  for (const auto& p : pairs) {
    if (p.full_space()) ++full_space;
    else if (engines.empty() || engines.back() != p.linear) engines.push_back(p.linear);
  }
  EXPECT_EQ(full_space, static_cast<int>(hemivem::available_krylov_solvers().size()));
  std::vector<std::string> done;
  hemivem::cli::PairRunOptions options;
  options.done = [&](const hemivem::cli::PairRun& r) { done.push_back(r.pair.label()); };
  const auto shared = hemivem::cli::run_pairs(scene, pairs, options);
  EXPECT_EQ(shared.assemblies, 1 + full_space);
  EXPECT_EQ(shared.condensations, static_cast<int>(engines.size()));
  EXPECT_EQ(shared.posings, full_space);
  ASSERT_EQ(shared.runs.size(), pairs.size());
  ASSERT_EQ(done.size(), pairs.size());
  const double scale = hemivem::cli::difference_scale(shared.runs);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const auto& r = shared.runs[i];
    SCOPED_TRACE(r.pair.label());
    EXPECT_EQ(r.pair.label(), pairs[i].label());
    EXPECT_EQ(done[i], pairs[i].label());
    ASSERT_TRUE(r.converged) << r.message;
    EXPECT_TRUE(r.guarantee) << r.broken;
    if (r.pair.full_space()) {  // its own assembly and posing, no condensation
      EXPECT_EQ(r.timings.count("condensation"), 0u);
      EXPECT_GT(r.timings.at("assembly"), 0.0);
      EXPECT_GE(r.timings.at("total"), r.timings.at("assembly") + r.timings.at("posing") + r.timings.at("full_space"));
      EXPECT_TRUE(std::isnan(r.margin));
    } else {
      EXPECT_EQ(r.timings.at("assembly"), shared.assembly_seconds);
      EXPECT_GE(r.timings.at("total"), shared.assembly_seconds + r.timings.at("condensation"));
    }
    EXPECT_EQ(r.seconds, shared.mesh_seconds + r.timings.at("total"));
    EXPECT_EQ(r.vertices, shared.built->mesh.num_vertices());
    EXPECT_LE(hemivem::cli::max_abs(r.u - shared.runs.front().u) / scale, 1e-6);  // Example 4.1 is unique
  }
  // the pairs of one engine share its condensation: the same time, measured once
  for (std::size_t i = 1; i < pairs.size(); ++i)
    if (pairs[i].linear == pairs[i - 1].linear && !pairs[i].full_space())
      EXPECT_EQ(shared.runs[i].timings.at("condensation"), shared.runs[i - 1].timings.at("condensation"));
}

// Every built Krylov engine is paired with ssn alone, after every condensed pair; a Krylov
// engine paired with another minimizer is refused before any work, naming the pair.
TEST(EnginePairs, EveryKrylovEngineIsPairedWithSsnAfterTheCondensedPairs) {
  const auto pairs = hemivem::cli::available_pairs();
  const auto krylov = hemivem::available_krylov_solvers();
  ASSERT_FALSE(krylov.empty()) << "eigen-cg is always built";
  const std::size_t condensed = hemivem::available_factorizations().size() * hemivem::available_minimizers().size();
  ASSERT_EQ(pairs.size(), condensed + krylov.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    SCOPED_TRACE(pairs[i].label());
    EXPECT_EQ(pairs[i].full_space(), i >= condensed);
    EXPECT_EQ(pairs[i].route(), i >= condensed ? "full_space" : "condensed");
    if (i < condensed) continue;
    EXPECT_EQ(pairs[i].linear, krylov[i - condensed]);
    EXPECT_EQ(pairs[i].minimizer, "ssn");
    EXPECT_EQ(pairs[i].label(), krylov[i - condensed] + "+ssn");
  }
  std::string other;
  for (const auto& m : hemivem::available_minimizers())
    if (m != "ssn" && other.empty()) other = m;
  if (other.empty()) return;
  const std::string error = hemivem::test::input_error_of(
      [&] { (void)hemivem::cli::run_pairs(hemivem::default_scene(), {{"eigen", "ssn"}, {"eigen-cg", other}}); });
  EXPECT_NE(error.find("eigen-cg+" + other), std::string::npos) << error;
  EXPECT_NE(error.find("ssn"), std::string::npos) << error;
}
