// The command's error estimate and adaptive solves: result.json's error_estimate and adapt,
// solution.vtu's error_indicator, the final mesh written as .poly2d, the summary's lines and
// the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <filesystem>
#include <regex>
#include <vector>
#include <string>

#include <nlohmann/json.hpp>

#include <hemivem/mesh/poly2d.hpp>

#include "test_support.hpp"

namespace hemivem {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::run_hemivem;
using test::scratch;
using test::slurp;

/// Whether `file` parses as XML whose root element is `root` (Python's xml.etree).
bool xml_root_is(const fs::path& file, const std::string& root) {
  const auto r = test::run_command("/usr/bin/python3 -c \"import sys, xml.etree.ElementTree as E; "
                                   "print(E.parse(sys.argv[1]).getroot().tag)\" " + file.string());
  return r.code == 0 && r.out == root + "\n";
}

TEST(CliAdapt, EverySolveReportsItsErrorEstimate) {
  const fs::path out = scratch("estimate");
  const auto r = run_hemivem("solve --n 8 --linear eigen --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("  error         estimate "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stages        assembly, condensation, minimize, back_substitution, estimate"), std::string::npos);
  const json j = json::parse(slurp(out / "result.json"));
  const json& e = j.at("error_estimate");
  const double energy = e.at("energy").get<double>(), norm = e.at("norm").get<double>();
  EXPECT_GT(energy, 0.0);
  EXPECT_NEAR(e.at("relative").get<double>(), energy / norm, 1e-15 * energy / norm);
  double sum = 0.0;
  for (const auto& [name, part] : e.at("parts").items()) sum += part.get<double>() * part.get<double>();
  EXPECT_NEAR(std::sqrt(sum), energy, 1e-12 * energy);
  EXPECT_TRUE(j.at("adapt").is_null());
  EXPECT_NE(slurp(out / "solution.vtu").find("Name=\"error_indicator\""), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "error.png") || r.out.find("skipped       error.png") != std::string::npos);
  EXPECT_FALSE(fs::exists(out / "mesh.poly2d"));  // a single solve's mesh is the scene's
  fs::remove_all(out);
}

TEST(CliAdapt, AnAdaptiveSolveWritesItsStepsAndItsFinalMesh) {
  const fs::path out = scratch("adapt");
  const auto r = run_hemivem("solve --n 4 --linear eigen --adapt --set adapt.target=0.1 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("hemivem: adapt step 0: 16 elements"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("  stopped       target: the relative error estimate"), std::string::npos) << r.out;
  const json j = json::parse(slurp(out / "result.json"));
  const json& a = j.at("adapt");
  EXPECT_EQ(a.at("stopped"), "target");
  EXPECT_EQ(a.at("target").get<double>(), 0.1);
  const json& steps = a.at("steps");
  ASSERT_GE(steps.size(), 2u);
  EXPECT_GT(steps.front().at("estimate").get<double>(), 0.1);
  EXPECT_LE(steps.back().at("estimate").get<double>(), 0.1);
  EXPECT_EQ(steps.back().at("estimate").get<double>(), j.at("error_estimate").at("relative").get<double>());
  EXPECT_EQ(steps.back().at("potential_energy").get<double>(), j.at("potential_energy").get<double>());
  // the final mesh, read back, is the one solved on
  const Poly2dMesh m = read_poly2d(out / "mesh.poly2d");
  EXPECT_EQ(m.mesh.num_vertices(), j.at("mesh").at("vertices").get<int>());
  EXPECT_EQ(m.mesh.num_elements(), steps.back().at("elements").get<int>());
  EXPECT_NE(j.at("mesh").at("description").get<std::string>().find("refined adaptively"), std::string::npos);
  // the resolved scene keeps the [adapt] table: it runs again as it ran
  EXPECT_NE(slurp(out / "scene.toml").find("[adapt]\ntarget = 0.1\n"), std::string::npos);
  fs::remove_all(out);
}

TEST(CliAdapt, TheStepsAreAParaViewSeries) {
  const fs::path out = scratch("adapt-series");
  const auto r = run_hemivem("solve --n 4 --linear eigen --adapt --set adapt.target=0.1 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(slurp(out / "result.json"));
  const json& steps = j.at("adapt").at("steps");
  ASSERT_GE(steps.size(), 2u);
  const std::vector<std::string> files = j.at("files").get<std::vector<std::string>>();
  auto listed = [&files](const std::string& f) { return std::find(files.begin(), files.end(), f) != files.end(); };
  EXPECT_TRUE(listed("adapt.pvd")) << j.at("files");
  // the collection names every step's file with the step as its time, in order
  const std::string pvd = slurp(out / "adapt.pvd");
  const std::regex data_set("<DataSet timestep=\"([0-9]+)\" group=\"\" part=\"0\" file=\"([^\"]+)\"/>");
  std::vector<std::pair<int, std::string>> entries;
  for (std::sregex_iterator it(pvd.begin(), pvd.end(), data_set), end; it != end; ++it)
    entries.emplace_back(std::stoi((*it)[1]), (*it)[2]);
  ASSERT_EQ(entries.size(), steps.size()) << pvd;
  EXPECT_TRUE(xml_root_is(out / "adapt.pvd", "VTKFile"));
  for (std::size_t k = 0; k < steps.size(); ++k) {
    EXPECT_EQ(entries[k].first, static_cast<int>(k));
    EXPECT_EQ(entries[k].second, "adapt-step-" + std::to_string(k) + ".vtu");
    const fs::path file = out / entries[k].second;
    ASSERT_TRUE(fs::exists(file)) << file;
    EXPECT_TRUE(listed(entries[k].second)) << entries[k].second;
    EXPECT_TRUE(xml_root_is(file, "VTKFile")) << file;
    // each step's own mesh
    const std::string vtu = slurp(file);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(vtu, m, std::regex("<Piece NumberOfPoints=\"([0-9]+)\" NumberOfCells=\"([0-9]+)\"")));
    EXPECT_EQ(std::stoi(m[1]), steps[k].at("vertices").get<int>()) << file;
    EXPECT_GE(std::stoi(m[2]), steps[k].at("elements").get<int>()) << file;
  }
  // the last step is the solve the folder holds
  EXPECT_EQ(slurp(out / ("adapt-step-" + std::to_string(steps.size() - 1) + ".vtu")), slurp(out / "solution.vtu"));
  // without the output vtu there is no series; the earlier run's steps go
  const auto again = run_hemivem("solve --n 4 --linear eigen --adapt --set adapt.target=0.1 "
                                 "--set 'output.write=[\"result-json\"]' --out " + out.string());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_FALSE(fs::exists(out / "adapt.pvd"));
  EXPECT_FALSE(fs::exists(out / "adapt-step-0.vtu"));
  fs::remove_all(out);
}

TEST(CliAdapt, AdaptiveSolvesRefuseWhatTheyCannotDo) {
  const fs::path out = scratch("adapt-refused");
  const auto r = run_hemivem("solve --n 4 --adapt --export-reduced " + (out / "red").string() + " --out " + out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--export-reduced"), std::string::npos) << r.err;
  const auto t = run_hemivem("solve --n 4 --set adapt.target=1.5 --out " + out.string());
  EXPECT_EQ(t.code, 2);
  EXPECT_NE(t.err.find("adapt.target: must be a relative error in (0, 1)"), std::string::npos) << t.err;
  const auto m = run_hemivem("solve --n 4 --adapt --linear mumps-mpi --out " + out.string());
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.err.find("--linear: an adaptive solve runs in one process"), std::string::npos) << m.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace hemivem
