// `hemivem bench` on three-dimensional scenes, run as a user runs it: the pairs on N x N x N
// cubes with their error against a nested reference (trilinear interpolation), the refinement
// study by doubling the generator's cell counts, and bad input refused before any work.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <hemivem/error.hpp>
#include <hemivem/mesh/generators3d.hpp>

#include "bench.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using hemivem::test::CommandRun;
using hemivem::test::run_command;
using hemivem::test::run_hemivem;
using hemivem::test::scenes_dir;
using hemivem::test::scratch;
using hemivem::test::slurp;

namespace {

std::string scene(const std::string& name) { return (scenes_dir() / name).string(); }

/// hemivem ARGS with HEMIVEM_MEMORY_LIMIT set to `limit`.
CommandRun run_limited(const std::string& limit, const std::string& args) {
  return run_command("HEMIVEM_MEMORY_LIMIT=" + limit + " " + std::string(HEMIVEM_BINARY) + " " + args);
}

}  // namespace

// A field trilinear in x, y, z is reproduced exactly between the vertices of a cubes mesh, and a
// mesh that is not the grid named is refused.
TEST(BenchInterpolateCubes, ReproducesATrilinearFieldAndRefusesAnotherGrid) {
  using namespace hemivem;
  const GridSize3 n(2, 3, 4);
  const Box box{-1.0, 1.0, 0.0, 0.6, 2.0, 3.0};
  const Mesh3D mesh = make_cubes(n, box);
  auto field = [](const Vec3& p) {
    return Vec3((1.0 + p.x()) * (2.0 - p.y()) * (0.5 + p.z()), 3.0 * p.x() * p.y() * p.z() - p.y(), 0.25 - p.z());
  };
  Eigen::VectorXd u(3 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) u.segment<3>(3 * v) = field(mesh.vertex(v));
  std::vector<Vec3> points{{-1.0, 0.0, 2.0}, {1.0, 0.6, 3.0}, {0.13, 0.41, 2.77}, {-0.9, 0.05, 2.999}, {0.5, 0.3, 2.5}};
  const std::array<double, 6> domain{box.x0, box.x1, box.y0, box.y1, box.z0, box.z1};
  const Eigen::VectorXd at = hemivem::cli::interpolate_cubes(mesh, u, n, domain, points);
  ASSERT_EQ(at.size(), 3 * static_cast<Eigen::Index>(points.size()));
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(at(3 * static_cast<Eigen::Index>(k) + c), field(points[k])(c), 1e-13) << k << " " << c;
  EXPECT_THROW(hemivem::cli::interpolate_cubes(mesh, u, GridSize3(2, 3, 5), domain, points), InputError);
  EXPECT_THROW(hemivem::cli::interpolate_cubes(mesh, u, GridSize3(4, 3, 2), domain, points), InputError);
}

// The 3D Example 4.1 on cubes: one row per pair and N on N x N x N cells, errors against the
// nested reference that fall with N and vanish at N = --ref, and the refinement study on three
// levels of doubled cell counts with finite estimates and effectivities, and the adaptive run.
TEST(CliBench3D, CubesRowsErrorsAndRefinementLevels) {
  const fs::path out = scratch("bench3d");
  const CommandRun r = run_hemivem("bench " + scene("example-4.1-3d.toml") +
                                   " --set 'mesh.n=[4,2,4]' --n 2,4,8 --ref 8 --levels 2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  // the table
  EXPECT_NE(r.out.find("on cubes n = 8"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("N: N x N x N cells"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cell counts doubled 2 times"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(", and adaptively ("), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("hemivem bench: uniform level 2"), std::string::npos) << r.err;

  const auto j = nlohmann::json::parse(slurp(out / "bench.json"));
  EXPECT_EQ(j["schema"], "hemivem-bench/6");
  EXPECT_EQ(j["dimension"], 3);
  EXPECT_EQ(j["mesh"], "cubes");
  ASSERT_TRUE(j["reference"].is_object()) << j["reference"];
  EXPECT_EQ(j["reference"]["n"], 8);
  EXPECT_EQ(j["reference"]["converged"], true);
  EXPECT_EQ(j["reference"]["vertices"], 9 * 9 * 9);
  EXPECT_NE(j["error_definition"].get<std::string>().find("trilinear"), std::string::npos);

  std::map<std::string, std::map<int, double>> error;  // pair -> N -> error
  for (const auto& row : j["rows"]) {
    const std::string pair = row["linear"].get<std::string>() + "+" + row["minimizer"].get<std::string>();
    const int n = row["n"];
    EXPECT_FALSE(error[pair].count(n)) << "duplicate row " << pair << " " << n;
    EXPECT_EQ(row["vertices"], (n + 1) * (n + 1) * (n + 1)) << pair;
    ASSERT_EQ(row["converged"], true) << pair << " n = " << n;
    ASSERT_TRUE(row["error"].is_number()) << pair << " n = " << n;
    error[pair][n] = row["error"];
  }
  ASSERT_GE(error.size(), 1u);
  EXPECT_EQ(j["rows"].size(), 3 * error.size());
  for (const auto& [pair, by_n] : error) {
    ASSERT_EQ(by_n.size(), 3u) << pair;
    EXPECT_GT(by_n.at(2), by_n.at(4)) << pair;
    EXPECT_GT(by_n.at(4), 1e-2) << pair;
    // N = --ref solves the reference's problem: the same solution to the certificate's tolerance
    EXPECT_LT(by_n.at(8), 1e-8) << pair;
  }

  const auto& f = j["refinement"];
  EXPECT_EQ(f["uniform_method"], "cells_doubled");
  EXPECT_EQ(f["levels"], 2);
  ASSERT_EQ(f["uniform"].size(), 3u) << f.dump(2);
  // [4, 2, 4] cells times 2^k, x = 0 and x = 1 clamped: 3 (nx - 1)(ny + 1)(nz + 1) unknowns
  for (int k = 0; k < 3; ++k) {
    const int nx = 4 << k, ny = 2 << k, nz = 4 << k;
    const auto& p = f["uniform"][static_cast<std::size_t>(k)];
    EXPECT_EQ(p["level"], k);
    EXPECT_EQ(p["unknowns"], 3 * (nx - 1) * (ny + 1) * (nz + 1)) << k;
    EXPECT_EQ(p["status"], "converged");
    ASSERT_TRUE(p["estimate"].is_number()) << p.dump();
    EXPECT_GT(p["estimate"].get<double>(), 0.0);
    ASSERT_TRUE(p["error"].is_number()) << p.dump();
    ASSERT_TRUE(p["effectivity"].is_number()) << p.dump();
    EXPECT_NEAR(p["effectivity"].get<double>(), p["estimate"].get<double>() / p["error"].get<double>(), 1e-12);
    // the estimate follows the true error: an effectivity of order 1 (about 1.05 here)
    EXPECT_GT(p["effectivity"].get<double>(), 0.3) << k;
    EXPECT_LT(p["effectivity"].get<double>(), 3.0) << k;
  }
  for (int k = 1; k < 3; ++k) {
    const auto& fine = f["uniform"][static_cast<std::size_t>(k)];
    const auto& coarse = f["uniform"][static_cast<std::size_t>(k - 1)];
    EXPECT_LT(fine["potential_energy"].get<double>(), coarse["potential_energy"].get<double>()) << k;
    EXPECT_LT(fine["estimate"].get<double>(), coarse["estimate"].get<double>()) << k;
  }
  ASSERT_TRUE(f["reference_energy"].is_number()) << f["reference"];
  EXPECT_LT(f["reference_energy"].get<double>(), f["uniform"][2]["potential_energy"].get<double>());
  EXPECT_EQ(f["below_reference"], 0);
  // the adaptive run from the scene's mesh towards the finest level's estimate, within its unknowns
  ASSERT_FALSE(f["adaptive"]["steps"].empty()) << f["adaptive"].dump();
  EXPECT_NE(f["adaptive"]["stopped"], "not_run") << f["adaptive"]["reason"];
  const auto& steps = f["adaptive"]["steps"];
  EXPECT_EQ(steps.front()["unknowns"], f["uniform"][0]["unknowns"]);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    EXPECT_LE(steps[k]["unknowns"].get<double>(), f["uniform"][2]["unknowns"].get<double>()) << k;
    EXPECT_EQ(steps[k]["status"], "converged") << k;
    ASSERT_TRUE(steps[k]["error"].is_number()) << steps[k].dump();
  }
  if (f["adaptive"]["stopped"] == "target")
    EXPECT_LE(steps.back()["estimate"].get<double>(), f["uniform"][2]["estimate"].get<double>());
  EXPECT_TRUE(fs::exists(out / "bench.csv"));
  fs::remove_all(out);
}

// Another 3D generator has no error (as non-squares in 2D) and its refinement levels remake the
// generator: Voronoi seeds doubling along each axis.
TEST(CliBench3D, VoronoiHasNoErrorAndItsLevelsDoubleTheSeeds) {
  const fs::path out = scratch("bench3d-voronoi");
  const CommandRun r = run_hemivem("bench " + scene("example-4.1-3d.toml") +
                                   " --set mesh.generator=\"voronoi\" --set 'mesh.n=[2,1,2]' --n 2 --levels 1 -q --out " +
                                   out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "bench.json"));
  EXPECT_EQ(j["dimension"], 3);
  EXPECT_TRUE(j["reference"].is_null()) << j["reference"];
  EXPECT_NE(j["error_definition"].get<std::string>().find("not cubes"), std::string::npos) << j["error_definition"];
  ASSERT_GE(j["rows"].size(), 1u);
  for (const auto& row : j["rows"]) EXPECT_TRUE(row["error"].is_null()) << row.dump();
  const auto& f = j["refinement"];
  ASSERT_EQ(f["uniform"].size(), 2u);
  // 4 seeds, then 32: the cells (and the unknowns) grow about eightfold
  const double ratio = f["uniform"][1]["unknowns"].get<double>() / f["uniform"][0]["unknowns"].get<double>();
  EXPECT_GT(ratio, 3.0) << f.dump(2);
  for (const auto& p : f["uniform"]) EXPECT_GT(p["estimate"].get<double>(), 0.0) << p.dump();
  // the adaptive run refines the Voronoi cells themselves (no true error without cubes)
  ASSERT_FALSE(f["adaptive"]["steps"].empty()) << f["adaptive"].dump();
  for (const auto& p : f["adaptive"]["steps"]) EXPECT_EQ(p["status"], "converged") << p.dump();
  fs::remove_all(out);
}

// A scene reading its mesh from a Gmsh file has no mesh size to set: refused, nothing written.
TEST(CliBench3D, AGmshSceneIsRefusedWithTheReason) {
  const fs::path out = scratch("bench3d-gmsh");
  const CommandRun r = run_hemivem("bench " + scene("gmsh-bracket-3d.toml") + " --n 2 --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("--n"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("l-bracket-3d.msh"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("mesh.generator"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// A reference or a refinement level that cannot fit, a reference not nested in a mesh and a level
// beyond the generators' 1000 cells per axis are refused before any solve (no progress line).
TEST(CliBench3D, SizesThatCannotWorkAreRefusedBeforeAnyWork) {
  const fs::path out = scratch("bench3d-refused");
  const std::string example = scene("example-4.1-3d.toml");
  auto refused = [&](const CommandRun& r, const std::string& flag, const std::string& fragment) {
    EXPECT_EQ(r.code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("error: " + flag + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("hemivem bench: reference"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("converged"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  };
  // cubes n = 48: about 6.7 GiB
  refused(run_limited("500M", "bench " + example + " --n 4 --ref 48 --levels 1 --out " + out.string()), "--ref",
          "cubes n = 48");
  // level 2 of [8, 4, 8] is [32, 16, 32]: about 560 MiB
  refused(run_limited("500M", "bench " + example + " --n 2 --ref 4 --levels 2 --out " + out.string()), "--levels",
          "refinement level 2");
  refused(run_hemivem("bench " + example + " --n 2,3 --ref 8 --levels 1 --out " + out.string()), "--ref",
          "--ref 8 is not a multiple of --n 3");
  refused(run_limited("1000000T", "bench " + example + " --set 'mesh.n=[1,1,1]' --n 2 --ref 4 --levels 10 --out " +
                                      out.string()),
          "--levels", "at most 1000 per axis");
}
