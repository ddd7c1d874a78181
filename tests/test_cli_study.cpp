// hemivem study: the prolongation and the Q1 energy directly, the command end to end.
#include <hemivem/vem/bilinear.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/vem/element.hpp>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "study.hpp"

#include "test_support.hpp"

namespace fs = std::filesystem;
using hemivem::Vec2;

namespace {

// u(x, y) = (1 + 2x - 3y + 4xy, -0.5 + x + 0.25y - 2xy): bilinear.
Vec2 bilinear(const Vec2& p) {
  const double x = p.x(), y = p.y();
  return {1 + 2 * x - 3 * y + 4 * x * y, -0.5 + x + 0.25 * y - 2 * x * y};
}

Eigen::VectorXd nodal(const hemivem::Mesh& mesh, Vec2 (*f)(const Vec2&)) {
  Eigen::VectorXd u(2 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) u.segment<2>(2 * v) = f(mesh.vertex(v));
  return u;
}

TEST(StudyProlongation, ExactForABilinearField) {
  // A bilinear field is bilinear on every coarse square, so its interpolant is itself.
  const hemivem::Rectangle domain{-1.0, 2.0, 0.5, 1.5};
  for (auto [nc, nf] : {std::pair{1, 4}, std::pair{3, 12}, std::pair{4, 8}, std::pair{5, 5}}) {
    const auto coarse = hemivem::make_squares(nc, domain);
    const auto fine = hemivem::make_squares(nf, domain);
    const Eigen::VectorXd p = hemivem::prolong_squares(nodal(coarse, bilinear), nc, nf);
    EXPECT_LT((p - nodal(fine, bilinear)).lpNorm<Eigen::Infinity>(), 1e-12) << nc << " -> " << nf;
  }
}

TEST(StudyProlongation, InterpolatesAHatFunctionBilinearly) {
  // The hat function of the centre vertex of 2 x 2 squares, at the vertices of 8 x 8.
  Eigen::VectorXd c = Eigen::VectorXd::Zero(2 * 9);
  c[2 * 4] = 1.0;  // u_x at vertex (1, 1)
  const Eigen::VectorXd p = hemivem::prolong_squares(c, 2, 8);
  for (int J = 0; J <= 8; ++J)
    for (int I = 0; I <= 8; ++I) {
      const double expected = (1 - std::abs(I - 4) / 4.0) * (1 - std::abs(J - 4) / 4.0);
      EXPECT_NEAR(p[2 * (J * 9 + I)], expected, 1e-15);
      EXPECT_EQ(p[2 * (J * 9 + I) + 1], 0.0);
    }
}

TEST(StudyProlongation, RejectsANonDividingN) {
  EXPECT_THROW(hemivem::prolong_squares(Eigen::VectorXd::Zero(2 * 16), 3, 8), hemivem::InputError);
  EXPECT_THROW(hemivem::prolong_squares(Eigen::VectorXd::Zero(5), 2, 8), hemivem::InputError);
}

TEST(StudyQ1Energy, ByHandForAShearedBilinearField) {
  // u = (xy, 0) on the unit square: eps_xx = y, eps_xy = x/2, so
  // sigma:eps = lambda y^2 + 2 mu (y^2 + 2 (x/2)^2) = (lambda + 2 mu) y^2 + mu x^2, integral (lambda + 3 mu)/3.
  const hemivem::Material m{65.0, 0.29};
  for (auto model : {hemivem::PlaneModel::strain, hemivem::PlaneModel::stress}) {
    const hemivem::Lame l = hemivem::lame(m, model);
    const hemivem::MaterialTable table(m, model);
    for (int n : {1, 2, 5}) {
      const auto mesh = hemivem::make_squares(n);
      const Eigen::VectorXd u = nodal(mesh, [](const Vec2& p) { return Vec2(p.x() * p.y(), 0.0); });
      EXPECT_NEAR(hemivem::q1_energy(mesh, table, u), (l.lambda + 3 * l.mu) / 3, 1e-12) << n;
    }
  }
  // Plane strain by the numbers: E = 65, nu = 0.29.
  const double lambda = 65.0 * 0.29 / (1.29 * 0.42), mu = 65.0 / 2.58;
  const auto mesh = hemivem::make_squares(3);
  const Eigen::VectorXd ux = nodal(mesh, [](const Vec2& p) { return Vec2(p.x(), 0.0); });
  EXPECT_NEAR(hemivem::q1_energy(mesh, hemivem::MaterialTable(m), ux), lambda + 2 * mu, 1e-11);
}

TEST(StudyQ1Energy, ElementMatchesTheVemConsistencyForLinearFields) {
  const hemivem::Lame l = hemivem::lame({65.0, 0.29}, hemivem::PlaneModel::strain);
  const std::array<Vec2, 4> v{Vec2(0.2, -0.1), Vec2(0.7, -0.1), Vec2(0.7, 0.15), Vec2(0.2, 0.15)};
  const auto K = hemivem::q1_stiffness(v, l);
  const hemivem::VemElement vem = hemivem::vem_element(std::span<const Vec2>(v.data(), 4), l);
  EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm());
  // Six linear fields: on them the VEM stiffness is its consistency part, exact.
  for (int f = 0; f < 6; ++f) {
    Eigen::Matrix<double, 8, 1> u;
    for (int k = 0; k < 4; ++k) {
      const double x = v[k].x(), y = v[k].y();
      const std::array<Vec2, 6> fields{Vec2(1, 0), Vec2(0, 1), Vec2(-y, x), Vec2(x, 0), Vec2(0, y), Vec2(y, x)};
      u.segment<2>(2 * k) = fields[f] + (f == 5 ? Vec2(0.3 * x, -0.7 * y) : Vec2::Zero());
    }
    const double q1 = u.dot(K * u), c = u.dot(vem.consistency * u);
    EXPECT_NEAR(q1, c, 1e-10 * (1 + std::abs(c))) << "field " << f;
    if (f < 3) {
      EXPECT_NEAR(q1, 0.0, 1e-10) << "rigid motion " << f;
    }
  }
  // The vertex order is free: a rotated list gives the permuted matrix.
  const std::array<Vec2, 4> w{v[2], v[3], v[0], v[1]};
  const auto Kw = hemivem::q1_stiffness(w, l);
  EXPECT_NEAR(Kw(0, 0), K(4, 4), 1e-12);
  EXPECT_NEAR(Kw(1, 6), K(5, 2), 1e-12);
  EXPECT_THROW(hemivem::q1_stiffness({Vec2(0, 0), Vec2(1, 0), Vec2(1.2, 1), Vec2(0, 1)}, l), hemivem::InputError);
}

// ---- end to end ----------------------------------------------------------------------------

using hemivem::test::CommandRun;
using hemivem::test::scratch;
using hemivem::test::slurp;
CommandRun run(const std::string& args) { return hemivem::test::run_hemivem(args); }


TEST(CliStudy, SmallStudyRunsAndItsErrorsDecrease) {
  const fs::path out = scratch("small");
  const CommandRun r = run("study --n 2,4 --ref 8 --json --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["schema"], "hemivem-study/2");
  EXPECT_EQ(j["reference"]["n"], 8);
  EXPECT_TRUE(j["converged"].get<bool>());
  ASSERT_EQ(j["rows"].size(), 2u);
  const double e2 = j["rows"][0]["error"], e4 = j["rows"][1]["error"];
  EXPECT_GT(e2, 0.0);
  EXPECT_LT(e2, 1.0);
  EXPECT_LT(e4, e2);
  EXPECT_TRUE(j["rows"][0]["rate"].is_null());
  EXPECT_NEAR(j["rows"][1]["rate"].get<double>(), std::log2(e2 / e4), 1e-12);
  EXPECT_DOUBLE_EQ(j["rows"][1]["paper"].get<double>(), 0.5207);
  EXPECT_DOUBLE_EQ(j["rows"][1]["independent"].get<double>(), 0.3626);
  EXPECT_TRUE(j["rows"][0]["paper"].is_null());
  // The a posteriori estimate and its effectivity against the study's own energy error
  // (both in ||v||_E^2 = 1/2 a(v, v)).
  for (const auto& row : j["rows"]) {
    ASSERT_TRUE(row["estimate"].is_number()) << row.dump();
    ASSERT_TRUE(row["effectivity"].is_number()) << row.dump();
    EXPECT_GT(row["estimate"].get<double>(), 0.0);
    EXPECT_GE(row["effectivity"].get<double>(), 0.5) << row.dump();
    EXPECT_LE(row["effectivity"].get<double>(), 3.0) << row.dump();
  }
  // One progress line per solve (reference and two), on stderr.
  std::size_t lines = 0;
  for (std::size_t p = r.err.find("hemivem study: N = "); p != std::string::npos; p = r.err.find("hemivem study: N = ", p + 1)) ++lines;
  EXPECT_EQ(lines, 3u) << r.err;
  // The files.
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "study.json")), j);
  const std::string csv = slurp(out / "study.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "h,N,error,rate,paper,independent,estimate,effectivity");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
  EXPECT_NE(csv.find("\n0.25,4,"), std::string::npos) << csv;
}

// study.png: an O(h) slope through the coarsest point, the reference N in the title, legend
// words a reader understands, units on the axes.
TEST(CliStudy, FigureHasAnOrderOneSlopeAndPlainWords) {
  const std::vector<hemivem::cli::StudyPoint> points{{0.25, 0.36, 0.52, 0.3626}, {0.125, 0.22, 0.31, 0.225}};
  const auto f = hemivem::cli::study_figure(points, true, 256);
  EXPECT_EQ(f.png, "study.png");
  EXPECT_NE(f.script.find(", 144 * x with lines"), std::string::npos) << f.script;  // 100 * 0.36 / 0.25
  EXPECT_NE(f.script.find("title 'O(h) reference slope'"), std::string::npos);
  EXPECT_NE(f.script.find("against the solution on 256 x 256 squares"), std::string::npos);
  EXPECT_NE(f.script.find("set xlabel 'mesh size h (scene units)'"), std::string::npos);
  EXPECT_NE(f.script.find("'paper (Feng, Han, Huang 2021, Table 1)'"), std::string::npos);
  EXPECT_EQ(f.script.find("DESIGN"), std::string::npos);
  EXPECT_EQ(hemivem::cli::study_figure(points, false, 64).script.find("paper"), std::string::npos);
}

TEST(CliStudy, TableNamesThePaperAndSaysItIsNotReproduced) {
  const fs::path out = scratch("table");
  const CommandRun r = run("study --n 2,4 --ref 8 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("paper"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("independent"), std::string::npos);
  EXPECT_NE(r.out.find("52.07 %"), std::string::npos);
  EXPECT_NE(r.out.find("not reproduced"), std::string::npos);
  EXPECT_NE(r.out.find("1/4"), std::string::npos);
  const CommandRun q = run("study -q --n 2 --ref 4 --out " + scratch("quiet").string());
  EXPECT_EQ(q.code, 0);
  EXPECT_EQ(q.out, "");
  EXPECT_EQ(q.err, "");
}

TEST(CliStudy, ReferenceValuesOnlyForExample41) {
  // A different problem has no paper or independent values; the stabilization and the plane
  // model keep them (the study is used to show their effect).
  const CommandRun gap = run("study -q --json --n 2,4 --ref 8 --set contact.gap=0.01 --out " + scratch("gap").string());
  ASSERT_EQ(gap.code, 0) << gap.err;
  const auto jg = nlohmann::json::parse(gap.out);
  EXPECT_TRUE(jg["rows"][1]["paper"].is_null());
  EXPECT_TRUE(jg["rows"][1]["independent"].is_null());
  EXPECT_FALSE(jg.contains("note"));
  const CommandRun stress = run("study -q --json --n 2,4 --ref 8 --set material.model=stress --out " + scratch("stress").string());
  ASSERT_EQ(stress.code, 0) << stress.err;
  const auto js = nlohmann::json::parse(stress.out);
  EXPECT_EQ(js["plane_model"], "plane-stress");
  EXPECT_DOUBLE_EQ(js["rows"][1]["paper"].get<double>(), 0.5207);
}

TEST(CliStudy, NonSquaresMeshIsAnInputError) {
  const CommandRun r = run("study --n 2 --ref 4 --set mesh.generator=voronoi --out " + scratch("voronoi").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("study needs nested square meshes (mesh.generator = squares)"), std::string::npos) << r.err;
}

TEST(CliStudy, NonDividingNIsAnInputError) {
  const fs::path out = scratch("dividing");
  const CommandRun r = run("study --n 2,3 --ref 8 --out " + out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("does not divide the reference N = 8"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "study.csv"));
  EXPECT_EQ(run("study --n 8 --ref 8 --out " + out.string()).code, 2);
}

}  // namespace
