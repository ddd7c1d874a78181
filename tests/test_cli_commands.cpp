// End-to-end tests of the hemivem command: they run the built binary.
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using hemivem::test::CommandRun;
using hemivem::test::scratch;
using hemivem::test::scenes_dir;
using hemivem::test::slurp;
CommandRun run(const std::string& args) { return hemivem::test::run_hemivem(args); }

TEST(Cli, DefaultSolveIsExample41AndWritesEveryOutput) {
  const fs::path out = scratch("default");
  const CommandRun r = run("solve --n 16 --out " + out.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["schema"], "hemivem-result/26");
  EXPECT_EQ(j["status"], "converged");
  // options are typed: numbers as JSON numbers, the tolerance exactly as given
  ASSERT_TRUE(j["options"]["tolerance"].is_number_float()) << j["options"];
  EXPECT_EQ(j["options"]["tolerance"].get<double>(), 1e-10);
  ASSERT_TRUE(j["options"]["max_iterations"].is_number_integer()) << j["options"];
  EXPECT_EQ(j["options"]["stabilization"], "2mu");
  EXPECT_EQ(j["mesh"]["description"], "squares n=16");
  EXPECT_LE(j["certificate"]["primal"].get<double>(), 1e-10);
  EXPECT_LE(j["certificate"]["dual"].get<double>(), 1e-10);
  EXPECT_EQ(j["contact"].size(), 15u);
  // no engine named: the fastest built one (cholmod, else mumps, else eigen)
  const auto built = hemivem::available_factorizations();
  std::string fastest = "eigen";
  for (const char* e : {"mumps", "cholmod"})
    if (std::find(built.begin(), built.end(), e) != built.end()) fastest = e;
  EXPECT_EQ(j["backends"]["linear"], fastest);
  EXPECT_EQ(j["backends"]["minimizer"], "ssn");
  for (const char* f : {"result.json", "contact.csv", "displacement.csv", "history.csv", "solution.vtu", "scene.toml"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "result.json")), j);
  // the resolved scene reproduces the run
  const fs::path again = scratch("again");
  const CommandRun r2 = run("solve " + (out / "scene.toml").string() + " --out " + again.string() + " --json");
  ASSERT_EQ(r2.code, 0);
  EXPECT_EQ(nlohmann::json::parse(r2.out)["contact"], j["contact"]);
  fs::remove_all(out);
  fs::remove_all(again);
}

// Whether `hemivem backends` lists an engine.
bool built(const std::string& engine) {
  const std::string list = run("backends").out;
  return list.find(" " + engine + " ") != std::string::npos || list.find(" " + engine + "\n") != std::string::npos;
}

TEST(Cli, EveryPairOfEnginesAgrees) {
  const CommandRun ref = run("solve --n 16 --out " + scratch("pair-ref").string() + " --json");
  ASSERT_EQ(ref.code, 0);
  const auto a = nlohmann::json::parse(ref.out)["contact"];
  for (const std::string linear : {"cholmod", "mumps"}) {
    for (const std::string minimizer : {"bundle-dca", "nlopt-mma", "ceres-active-set"}) {
      const CommandRun r = run("solve --n 16 --linear " + linear + " --minimizer " + minimizer + " --tol 1e-9 --out " +
                        scratch("pair").string() + " --json");
      if (!built(linear) || !built(minimizer)) {  // an engine that was not built: an input error
        EXPECT_EQ(r.code, 2) << linear << " " << minimizer;
        continue;
      }
      ASSERT_EQ(r.code, 0) << linear << " " << minimizer << ": " << r.err;
      const auto b = nlohmann::json::parse(r.out)["contact"];
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t i = 0; i < a.size(); ++i)
        EXPECT_NEAR(a[i]["u_nu"].get<double>(), b[i]["u_nu"].get<double>(), 1e-8) << linear << " " << minimizer;
    }
  }
}

TEST(Cli, EveryShippedSceneRuns) {
  for (const auto& entry : fs::directory_iterator(scenes_dir())) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().filename().string();
    const CommandRun r = run("solve " + entry.path().string() + " --n 8 --out " + scratch("scene").string() + " -q");
    // a scene reading a mesh file refuses --n: run those without it
    const CommandRun r2 = r.code == 2 ? run("solve " + entry.path().string() + " --out " + scratch("scene").string() + " -q") : r;
    EXPECT_EQ(r2.code, 0) << name << ": " << r2.err;
  }
}

TEST(Cli, ExportedReducedProblemSolvesToTheSameAnswer) {
  const fs::path out = scratch("export"), red = scratch("reduced");
  const CommandRun r = run("solve --n 16 --out " + out.string() + " --export-reduced " + red.string() + " --json");
  ASSERT_EQ(r.code, 0);
  const auto contact = nlohmann::json::parse(r.out)["contact"];
  for (const std::string m : {"ssn", "bundle-dca"}) {
    const CommandRun q = run("minimize " + red.string() + " --minimizer " + m + " --json");
    ASSERT_EQ(q.code, 0) << q.out;
    const auto j = nlohmann::json::parse(q.out);
    EXPECT_EQ(j["converged"], true);
    ASSERT_EQ(j["a"].size(), contact.size());
    for (std::size_t i = 0; i < contact.size(); ++i)
      EXPECT_NEAR(j["a"][i].get<double>(), contact[i]["u_nu"].get<double>(), 1e-9);
  }
  fs::remove_all(out);
  fs::remove_all(red);
}

TEST(Cli, ExitCodes) {
  const fs::path out = scratch("codes");
  EXPECT_EQ(run("solve --n 8 --out " + out.string() + " -q").code, 0);
  EXPECT_EQ(run("solve --no-such-flag").code, 2);
  EXPECT_EQ(run("solve --linear pardiso --out " + out.string()).code, 2);
  EXPECT_EQ(run("solve --set contact.gap=-1 --out " + out.string()).code, 2);
  EXPECT_EQ(run("solve --set contcat.gap=1 --out " + out.string()).code, 2);
  EXPECT_EQ(run("solve " + (hemivem::test::data_dir() / "scenes-bad" / "negative-gap.toml").string()).code, 2);
  // not converged: one iteration of the bundle method cannot reach 1e-14; results still written
  const fs::path nc = scratch("not-converged");
  const CommandRun r = run("solve --n 8 --minimizer bundle-dca --tol 1e-14 --set solver.max_iterations=1 --out " + nc.string() + " --json");
  EXPECT_EQ(r.code, 3);
  EXPECT_EQ(nlohmann::json::parse(r.out)["converged"], false);
  EXPECT_TRUE(fs::exists(nc / "result.json"));
  EXPECT_EQ(run("backends").code, 0);
  EXPECT_EQ(run("--version").code, 0);
  fs::remove_all(out);
  fs::remove_all(nc);
}

TEST(Cli, ErrorsNameTheProblem) {
  const CommandRun a = run("solve --set contcat.gap=1");
  EXPECT_NE(a.err.find("did you mean 'contact'"), std::string::npos) << a.err;
  const CommandRun b = run("solve --linear pardiso");
  EXPECT_NE(b.err.find("available:"), std::string::npos) << b.err;
  const CommandRun c = run("minimize " + fs::temp_directory_path().string());
  EXPECT_NE(c.err.find("S.mtx"), std::string::npos) << c.err;
}

}  // namespace

TEST(Cli, EngineParametersFromTheScene) {
  const fs::path dir = scratch("parameters");
  fs::create_directories(dir);
  const fs::path good = dir / "good.toml";
  {
    std::ofstream f(good);
    f << "schema_version = 1\n[clamped]\nside = [\"left\", \"right\"]\n[solver]\nminimizer = \"ssn\"\n\n[solver.parameters]\narmijo = "
         "1e-3\nmax_backtracks = 7\n";
  }
  const CommandRun ok = run("solve " + good.string() + " --n 8 --out " + (dir / "out").string() + " --json");
  ASSERT_EQ(ok.code, 0) << ok.err;
  const auto j = nlohmann::json::parse(ok.out);
  EXPECT_NE(j["scene"]["toml"].get<std::string>().find("[solver.parameters]"), std::string::npos)
      << "the resolved scene keeps them";
  // a value of the wrong kind, an unknown name: exit 2, the scene's line, the engine and the field
  for (const auto& [line, field] : std::vector<std::pair<std::string, std::string>>{
           {"max_backtracks = 1e20", "max_backtracks"}, {"armijo = 0.9", "armijo"}, {"newton_steps = 3", "newton_steps"}}) {
    const fs::path bad = dir / "bad.toml";
    {
      std::ofstream f(bad);
      f << "schema_version = 1\n[solver]\nminimizer = \"ssn\"\n\n[solver.parameters]\n" << line << "\n";
    }
    const fs::path out = dir / "bad-out";
    const CommandRun r = run("solve " + bad.string() + " --n 8 --out " + out.string());
    EXPECT_EQ(r.code, 2) << line;
    EXPECT_NE(r.err.find(bad.string() + ":5"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(field), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("ssn"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "result.json"));
  }
  // other engines of `check` keep their defaults: the parameters are ssn's
  const CommandRun c = run("check " + good.string() + " --n 8 --json");
  EXPECT_EQ(c.code, 0) << c.err;
}

// `hemivem mesh` writes a generated mesh of a rectangle or of a polygon; bad polygons are
// refused with the defect named and nothing written.
TEST(Cli, MeshCommandWritesRectanglesAndPolygons) {
  const fs::path dir = scratch("mesh-command");
  fs::create_directories(dir);
  EXPECT_EQ(run("mesh squares --n 3 --domain 0 2 0 1 -o " + (dir / "r.poly2d").string()).code, 0);
  EXPECT_EQ(hemivem::read_poly2d(dir / "r.poly2d").mesh.num_elements(), 9);
  // --ny: cells along y (square cells on a 2 x 1 domain)
  EXPECT_EQ(run("mesh squares --n 6 --ny 3 --domain 0 2 0 1 -o " + (dir / "w.poly2d").string()).code, 0);
  const hemivem::Mesh wide = hemivem::read_poly2d(dir / "w.poly2d").mesh;
  EXPECT_EQ(wide.num_elements(), 18);
  for (int e = 0; e < wide.num_elements(); ++e) EXPECT_NEAR(wide.area(e), 1.0 / 9.0, 1e-15);
  const CommandRun ok = run("mesh voronoi --n 6 --polygon 0 0 1 0 1 0.5 0.5 0.5 0.5 1 0 1 -o " + (dir / "l.poly2d").string());
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NEAR(hemivem::read_poly2d(dir / "l.poly2d").mesh.total_area(), 0.75, 1e-12);
  const std::vector<std::pair<std::string, std::string>> bad{
      {"voronoi --n 6 --polygon 0 0 1 0 1 1 0", "pairs of coordinates"},
      {"triangles --n 6 --polygon 0 0 1 1 1 0 0 1", "not simple"},
      {"squares --n 6 --polygon 0 0 1 0 1 1", "needs a rectangular domain"},
      {"voronoi --n 6 --ny 2 --polygon 0 0 1 0 1 1", "--ny excludes --polygon"},
  };
  for (const auto& [args, fragment] : bad) {
    const CommandRun r = run("mesh " + args + " -o " + (dir / "bad.poly2d").string());
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad.poly2d")) << args;
  }
}

// A problem that nothing drives is solved (u = 0) but warned about on stderr and in
// result.json; a scene without a title is named after its file, never "Example 4.1".
TEST(Cli, TrivialProblemsAreWarnedAbout) {
  const fs::path dir = scratch("trivial");
  fs::create_directories(dir);
  {
    std::ofstream(dir / "bare.toml") << "schema_version = 1\n[clamped]\nside = [\"left\", \"right\"]\n";
  }
  const CommandRun r = run("solve " + (dir / "bare.toml").string() + " --n 4 --out " + (dir / "out").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("hemivem: warning: nothing drives this problem"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(dir / "out" / "result.json"));
  ASSERT_EQ(j.at("warnings").size(), 1u);
  EXPECT_EQ(j.at("scene").at("name"), "bare");
  const CommandRun paper = run("solve --n 4 --out " + (dir / "paper").string() + " -q");
  EXPECT_EQ(paper.err.find("warning"), std::string::npos) << paper.err;
  EXPECT_TRUE(nlohmann::json::parse(slurp(dir / "paper" / "result.json")).at("warnings").empty());
}

// After a run the output folder holds exactly that run's files (result.json lists them):
// names hemivem writes that the run did not are removed, nothing else is touched; a problem
// without contact writes no contact table, history or u_nu plot; output.write switches the
// plots off.
TEST(Cli, OutputFolderHoldsExactlyTheRunsFiles) {
  const fs::path out = scratch("exact-outputs");
  ASSERT_EQ(run("solve --n 4 --out " + out.string() + " -q").code, 0);
  std::ofstream(out / "notes.txt") << "mine\n";
  auto listing = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(out)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  auto files_of = [&] {
    auto v = nlohmann::json::parse(slurp(out / "result.json")).at("files").get<std::vector<std::string>>();
    v.push_back("notes.txt");
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(listing(), files_of());
  const CommandRun lin = run("solve " + (scenes_dir() / "linear-elastic.toml").string() + " --n 4 --out " + out.string());
  ASSERT_EQ(lin.code, 0) << lin.err;
  EXPECT_EQ(listing(), (std::vector<std::string>{"deformed.png", "displacement.csv", "error.png", "notes.txt",
                                                 "result.json", "scene.toml", "solution.vtu", "stress.csv"}));
  EXPECT_EQ(listing(), files_of());
  EXPECT_NE(lin.out.find("removed       contact.csv, history.csv, u_nu.png"), std::string::npos) << lin.out;
  EXPECT_NE(lin.out.find("(no contact: one linear solve)"), std::string::npos) << lin.out;
  ASSERT_EQ(run("solve --n 4 --set output.write=[\\\"result-json\\\"] --out " + out.string() + " -q").code, 0);
  EXPECT_EQ(listing(), (std::vector<std::string>{"notes.txt", "result.json", "scene.toml"}));
  EXPECT_EQ(slurp(out / "notes.txt"), "mine\n");
}

// The output folder is checked before any work: a file, or a folder that cannot be made,
// fails at once with exit 2 and nothing written.
TEST(Cli, OutputFolderIsCheckedFirst) {
  const fs::path dir = scratch("out-checked");
  fs::create_directories(dir);
  std::ofstream(dir / "file") << "x";
  const CommandRun a = run("solve --n 4 --out " + (dir / "file").string());
  EXPECT_EQ(a.code, 2);
  EXPECT_NE(a.err.find("the output folder is a file, not a folder"), std::string::npos) << a.err;
  EXPECT_EQ(a.err.find("vertices"), std::string::npos) << "no work before the check: " << a.err;
  const CommandRun b = run("solve --n 4 --out " + (dir / "file" / "sub").string());
  EXPECT_EQ(b.code, 2);
  EXPECT_NE(b.err.find("is not a folder"), std::string::npos) << b.err;
  EXPECT_EQ(slurp(dir / "file"), "x");
}

// Flags and --set overrides are validated together: their order does not matter.
TEST(Cli, OverridesInAnyOrder) {
  for (const std::string order : {"--set contact.parameters.sigma=0.5 --set contact.law=kinked",
                                  "--set contact.law=kinked --set contact.parameters.sigma=0.5"}) {
    const CommandRun r = run("solve --n 4 " + order + " --out " + scratch("order").string() + " -q");
    EXPECT_EQ(r.code, 0) << order << ": " << r.err;
  }
}

// Command-line errors in one voice: "hemivem: error: " and exit 2, the flag named, no
// internal function names, numbers as given, suggestions only when close.
TEST(Cli, CommandLineErrorsInOneVoice) {
  const std::string out = " --out " + scratch("voice").string();
  const std::vector<std::pair<std::string, std::string>> cases{
      {"sovle", "unknown command 'sovle'; did you mean 'solve'?"},
      {"", "a command is required"},
      {"solve --mesh mesh.txt" + out, "--mesh: 'mesh.txt' is neither a mesh generator"},
      {"solve --mesh voronio" + out, "did you mean 'voronoi'?"},
      {"solve --tol -1" + out, "--tol: expected a number > 0, got '-1'"},
      {"check --linear eigen", "'check' takes no option --linear"},
      {"solve --bogus", "'solve' takes no option --bogus"},
      {"mesh hexagons --n 3 -o " + scratch("voice.poly2d").string(), "unknown mesh generator 'hexagons' (expected"},
      {"solve --set contact.adhesion=1" + out, "unknown key 'adhesion' in [contact]"},
  };
  for (const auto& [args, fragment] : cases) {
    const CommandRun r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(r.err.rfind("hemivem: error: ", 0), 0u) << args << ": " << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << args << ": " << r.err;
    for (const char* noise : {"make_", "estimate_memory", "did you mean 'side'", "179769313486231570814527423731704356798070567"})
      EXPECT_EQ(r.err.find(noise), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(scratch("voice")));
  const CommandRun m = run("mesh squares --n 2 -o " + scratch("said.poly2d").string());
  EXPECT_NE(m.out.find("hemivem mesh: wrote "), std::string::npos) << m.out;
}
