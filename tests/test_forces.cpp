// The balance of forces on the body (ForceBalance): the applied load, the reaction of each
// Dirichlet part named as in the scene, the contact resultant; in result.json and the summary.
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/report.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/contact/forces.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <numeric>
#include <sstream>

using namespace hemivem;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

app::SceneSolve solve_text(const std::string& text) {
  const Scene scene = parse_scene_string("schema_version = 1\n" + text, "forces.toml");
  return app::solve_scene(scene);
}

const ForceBalance::Reaction* reaction(const ForceBalance& b, const std::string& name) {
  const auto it = std::find_if(b.reactions.begin(), b.reactions.end(), [&](const auto& r) { return r.name == name; });
  return it == b.reactions.end() ? nullptr : &*it;
}

/// A generated mesh of more than 32 cells along x made coarser (the ratio nx : ny kept), so
/// that every shipped scene solves in a moment.
void coarsen(Scene& scene) {
  if (!scene.bodies.empty() || !scene.mesh.file.empty() || scene.mesh.n <= 32) return;  // [[body]]: small meshes of their own
  if (!scene.mesh.ny) {
    apply_override(scene, "mesh.n=32");
    return;
  }
  const int ny = std::max(1, *scene.mesh.ny * 32 / scene.mesh.n);
  apply_override(scene, "mesh.n=[32, " + std::to_string(ny) + "]");
}

}  // namespace

// A bar [0, 4] x [0, 1] clamped on the left, pulled on the right by a uniform traction t: the
// applied load is t times the side's length 1, and the clamp holds all of it.
TEST(Forces, ClampedBarUnderUniformTraction) {
  const auto s = solve_text(R"(
[mesh]
generator = "squares"
n = [8, 2]
domain = [0.0, 4.0, 0.0, 1.0]
[material]
E = 100.0
nu = 0.3
[clamped]
side = "left"
[[loads.traction]]
side = "right"
value = [2.5, -0.5]
)");
  ASSERT_TRUE(s.solution.converged());
  const ForceBalance& b = s.solution.forces;
  EXPECT_NEAR(b.applied.x(), 2.5, 1e-14);
  EXPECT_NEAR(b.applied.y(), -0.5, 1e-14);
  ASSERT_EQ(b.reactions.size(), 1u);
  EXPECT_EQ(b.reactions[0].name, "clamped");
  EXPECT_NEAR(b.reactions[0].force.x(), -2.5, 1e-12);
  EXPECT_NEAR(b.reactions[0].force.y(), 0.5, 1e-12);
  EXPECT_EQ(b.contact, Vec2::Zero());
  EXPECT_LT(b.residual(), 1e-12);
}

// The same bar held at both ends by two [[dirichlet]] parts under a uniform body force f: the
// load is f times the area 4, and by symmetry each end holds half of it.
TEST(Forces, BodyForceSharedByTwoNamedParts) {
  const auto s = solve_text(R"(
[mesh]
generator = "squares"
n = [8, 2]
domain = [0.0, 4.0, 0.0, 1.0]
[material]
E = 100.0
nu = 0.3
[[dirichlet]]
side = "left"
value = [0.0, 0.0]
[[dirichlet]]
side = "right"
value = [0.0, 0.0]
[loads]
body_force = [3.0, 0.0]
)");
  ASSERT_TRUE(s.solution.converged());
  const ForceBalance& b = s.solution.forces;
  EXPECT_NEAR(b.applied.x(), 12.0, 1e-13);
  EXPECT_NEAR(b.applied.y(), 0.0, 1e-13);
  ASSERT_EQ(b.reactions.size(), 2u);
  const auto* left = reaction(b, "dirichlet[0]");
  const auto* right = reaction(b, "dirichlet[1]");
  ASSERT_TRUE(left && right);
  EXPECT_NEAR(left->force.x(), -6.0, 1e-11);
  EXPECT_NEAR(right->force.x(), -6.0, 1e-11);
  EXPECT_NEAR(left->force.y(), -right->force.y(), 1e-11) << "mirror images";
  EXPECT_LT(b.residual(), 1e-12);
}

// A vertex that two parts prescribe counts for the later one, whose value it takes: a clamp
// of the bottom and a roller (ux only) on the left share the corner (0, 0). Listed in either
// order, the solution is the same and the corner's x reaction moves from one part to the other.
TEST(Forces, SharedVertexCountsForTheLaterPart) {
  const std::string head = R"(
[mesh]
generator = "squares"
n = 4
[material]
E = 100.0
nu = 0.3
[[loads.traction]]
side = "right"
value = [-1.0, 0.5]
)";
  const std::string bottom = "[[dirichlet]]\nside = \"bottom\"\nvalue = [0.0, 0.0]\n";
  const std::string left = "[[dirichlet]]\nside = \"left\"\nux = 0.0\n";
  const auto roller_last = solve_text(head + bottom + left);
  const auto roller_first = solve_text(head + left + bottom);
  ASSERT_TRUE(roller_last.solution.converged() && roller_first.solution.converged());
  EXPECT_LT((roller_last.solution.u - roller_first.solution.u).norm(), 1e-12 * roller_last.solution.u.norm());
  const ForceBalance& a = roller_last.solution.forces;   // dirichlet[0] bottom, [1] left
  const ForceBalance& b = roller_first.solution.forces;  // dirichlet[0] left, [1] bottom
  EXPECT_EQ(a.reactions[1].force.y(), 0.0) << "a roller in x holds nothing in y";
  EXPECT_EQ(b.reactions[0].force.y(), 0.0);
  const double corner = a.reactions[1].force.x() - b.reactions[0].force.x();
  EXPECT_GT(std::abs(corner), 1e-3) << "the corner carries part of the horizontal load";
  EXPECT_NEAR(b.reactions[1].force.x() - a.reactions[0].force.x(), corner, 1e-12);
  EXPECT_NEAR(a.reactions[0].force.x() + a.reactions[1].force.x(), 1.0, 1e-12);
  EXPECT_NEAR(a.reactions[0].force.y(), -0.5, 1e-12);
  EXPECT_LT(a.residual(), 1e-12);
  EXPECT_LT(b.residual(), 1e-12);
}

// Every scene shipped in scenes/ (on a mesh of at most 32 cells across): applied load,
// reactions and contact resultant balance.
TEST(Forces, BalanceOnEveryShippedScene) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(test::scenes_dir()))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 17u);
  int solved = 0;
  double worst = 0.0;
  for (const auto& file : files) {
    SCOPED_TRACE(file.filename().string());
    Scene scene = parse_scene(file);
    if (!scene.mesh.file.empty() && !fs::exists(scene.mesh.file)) continue;  // a mesh of the shared folder
    if (scene.dimension() == 3) {  // a three-dimensional scene, on at most 6 cells per axis
      if (scene.bodies.empty() && scene.mesh.file.empty() && scene.mesh.n > 6) apply_override(scene, "mesh.n=6");
      const auto s3 = app::solve_scene_3d(scene);
      ASSERT_TRUE(s3.solution.converged()) << s3.solution.message;
      const ForceBalance3D& b = s3.solution.forces;
      EXPECT_GT(b.applied.norm() + b.contact.norm() + b.internal, 0.0) << "something loads the body";
      EXPECT_EQ(b.contact, external_contact_resultant(s3.solution.contact));
      if (scene.bodies.empty()) EXPECT_EQ(b.contact, s3.solution.contact_force());
      EXPECT_LT(b.residual(), 1e-10);
      worst = std::max(worst, b.residual());
      std::cout << file.filename().string() << ": balance residual " << b.residual() << "\n";
      ++solved;
      continue;
    }
    coarsen(scene);
    const auto s = app::scene_is_path(scene) ? app::solve_scene_path(scene) : app::solve_scene(scene);
    ASSERT_TRUE(s.solution.converged()) << s.solution.message;
    const ForceBalance& b = s.solution.forces;
    double reactions = 0.0;
    for (const auto& r : b.reactions) reactions = std::max(reactions, r.force.norm());
    // loads, supports pressing the body, or (two rings pressed into each other) bodies on bodies
    EXPECT_GT(b.applied.norm() + b.contact.norm() + reactions + b.internal, 0.0) << "something loads the body";
    // the contact of foundations and obstacles: two bodies' forces on each other cancel
    EXPECT_EQ(b.contact, external_contact_resultant(s.solution.contact));
    if (scene.bodies.empty()) EXPECT_EQ(b.contact, s.solution.contact_force());
    EXPECT_LT(b.residual(), 1e-10);
    worst = std::max(worst, b.residual());
    std::cout << file.filename().string() << ": balance residual " << b.residual() << "\n";
    ++solved;
  }
  EXPECT_GE(solved, 16);
  RecordProperty("worst_balance_residual", std::to_string(worst));
}

// Example 4.1: the contact resultant of result.json is the sum over contact.csv's nodes of the
// force -(law_force + reaction) times the normal (nx, ny), and the summary prints the balance.
TEST(Forces, Example41ContactResultantFromContactCsv) {
  Scene scene = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");
  apply_override(scene, "mesh.n=16");
  const auto s = app::solve_scene(scene);
  ASSERT_TRUE(s.solution.converged());
  const fs::path dir = test::scratch("forces-ex41");
  const std::vector<std::string> files{"result.json", "contact.csv"};
  app::write_results(dir, scene, s, &files);

  std::ifstream csv(dir / "contact.csv");
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(line.rfind("vertex,x,y,u_nu,law_force,reaction,pressure,state,gap,nx,ny", 0), 0u);
  Vec2 sum = Vec2::Zero();
  double largest = 0.0;
  int nodes = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> col;
    std::stringstream row(line);
    for (std::string c; std::getline(row, c, ',');) col.push_back(c);
    ASSERT_GE(col.size(), 11u);
    const double force = std::stod(col[4]) + std::stod(col[5]);
    sum -= force * Vec2(std::stod(col[9]), std::stod(col[10]));
    largest = std::max(largest, std::abs(force));
    ++nodes;
  }
  ASSERT_GT(nodes, 0);
  ASSERT_GT(sum.y(), 0.0) << "the foundation pushes the body up";

  std::ifstream in(dir / "result.json");
  const json j = json::parse(in);
  EXPECT_EQ(j.at("schema"), "hemivem-result/26");
  const json& f = j.at("forces");
  EXPECT_NEAR(f.at("contact")[0].get<double>(), sum.x(), 1e-13 * largest * nodes);
  EXPECT_NEAR(f.at("contact")[1].get<double>(), sum.y(), 1e-13 * largest * nodes);
  EXPECT_NEAR(f.at("applied")[0].get<double>(), 0.0, 1e-14);
  EXPECT_NEAR(f.at("applied")[1].get<double>(), -8.0, 1e-13) << "traction -8 on the top side of length 1";
  ASSERT_TRUE(f.at("reactions").contains("clamped"));
  EXPECT_EQ(f.at("reactions").size(), 1u);
  const double ry = f.at("reactions").at("clamped")[1].get<double>();
  EXPECT_NEAR(ry + sum.y() - 8.0, 0.0, 1e-10 * 8.0);
  EXPECT_LT(f.at("balance_residual").get<double>(), 1e-10);

  const std::string summary = app::full_report(s, app::run_info(scene, s));
  EXPECT_NE(summary.find("applied (0, -8), reactions clamped ("), std::string::npos) << summary;
  EXPECT_NE(summary.find(", contact (0, "), std::string::npos) << summary;
  EXPECT_NE(summary.find("  balance       |applied + reactions + contact| = "), std::string::npos) << summary;
  EXPECT_NE(summary.find("summed over the contact nodes (a sum, not a resultant)"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("in total"), std::string::npos) << "a sum of normal forces is not a total force";
  fs::remove_all(dir);
}

// apply_stiffness is K u of the assembled global stiffness on the rows asked for, 0 elsewhere.
TEST(Forces, ApplyStiffnessIsTheAssembledStiffnessTimesU) {
  Scene scene = parse_scene(test::scenes_dir() / "paper-example-4.1-voronoi.toml");
  apply_override(scene, "mesh.n=8");
  const auto built = build_problem(scene);
  const ElasticityProblem& e = built->problem.elasticity;
  const int n = 2 * built->mesh.num_vertices();
  Eigen::VectorXd u(n);
  for (int d = 0; d < n; ++d) u(d) = std::sin(1.0 + 0.37 * d);
  const Eigen::VectorXd Ku = assemble_stiffness(built->mesh, e.materials, e.stabilization) * u;
  std::vector<char> rows(static_cast<std::size_t>(n), 1);
  EXPECT_LT((apply_stiffness(built->mesh, e.materials, e.stabilization, u, rows) - Ku).norm(), 1e-12 * Ku.norm());
  for (int d = 0; d < n; ++d) rows[static_cast<std::size_t>(d)] = d % 3 == 0;
  const Eigen::VectorXd some = apply_stiffness(built->mesh, e.materials, e.stabilization, u, rows);
  for (int d = 0; d < n; ++d) {
    if (d % 3 == 0) EXPECT_NEAR(some(d), Ku(d), 1e-12 * Ku.norm());
    else EXPECT_EQ(some(d), 0.0);
  }
}

// The load and K u at the dofs of some vertices alone (a process's own vertices) are the whole
// vectors' entries there, to the bit, in the plane and in a solid, with a body force and tractions.
template <int dim>
void expect_the_whole_at_some_vertices(const char* scene_file, const std::string& mesh, const std::string& body_force) {
  Scene scene = parse_scene(test::scenes_dir() / scene_file);
  apply_override(scene, mesh);
  apply_override(scene, "loads.body_force=" + body_force);
  const auto built = build_problem<dim>(scene);
  const BasicElasticityProblem<dim>& e = built->problem.elasticity;
  const MeshOf<dim>& m = *e.mesh;
  const int n = dim * m.num_vertices();
  Eigen::VectorXd u(n);
  for (int d = 0; d < n; ++d) u(d) = std::sin(1.0 + 0.37 * d);
  std::vector<int> vertices;  // every third vertex, and the last
  for (int v = 1; v < m.num_vertices(); v += 3) vertices.push_back(v);
  if (vertices.back() != m.num_vertices() - 1) vertices.push_back(m.num_vertices() - 1);
  std::vector<char> whole_rows(static_cast<std::size_t>(n), 0), rows(dim * vertices.size(), 0);
  for (std::size_t p = 0; p < vertices.size(); ++p)
    for (int c = 0; c < dim; ++c)
      if ((p + static_cast<std::size_t>(c)) % 2 == 0)
        rows[dim * p + c] = whole_rows[static_cast<std::size_t>(dim * vertices[p] + c)] = 1;
  const Eigen::VectorXd f = assemble_load(m, e.body_force, e.tractions);
  const Eigen::VectorXd Ku = apply_stiffness(m, e.materials, e.stabilization, u, whole_rows);
  const Eigen::VectorXd f_at = assemble_load_at(m, e.body_force, e.tractions, vertices);
  const Eigen::VectorXd Ku_at = apply_stiffness_at(m, e.materials, e.stabilization, u, vertices, rows);
  ASSERT_EQ(f_at.size(), static_cast<Eigen::Index>(dim * vertices.size()));
  ASSERT_EQ(Ku_at.size(), f_at.size());
  int loaded = 0, applied = 0;
  for (std::size_t p = 0; p < vertices.size(); ++p)
    for (int c = 0; c < dim; ++c) {
      const Eigen::Index at = static_cast<Eigen::Index>(dim * p + c), d = dim * vertices[p] + c;
      EXPECT_EQ(f_at(at), f(d)) << "vertex " << vertices[p] << " component " << c;
      EXPECT_EQ(Ku_at(at), Ku(d)) << "vertex " << vertices[p] << " component " << c;
      loaded += f(d) != 0.0;
      applied += rows[static_cast<std::size_t>(at)] != 0 && Ku(d) != 0.0;
    }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(applied, 0);
  // every vertex: the whole vectors themselves
  std::vector<int> all(static_cast<std::size_t>(m.num_vertices()));
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(assemble_load_at(m, e.body_force, e.tractions, all), f);
  EXPECT_EQ(apply_stiffness_at(m, e.materials, e.stabilization, u, all, whole_rows), Ku);
  // vertices out of order, or out of the mesh, and flags of another number
  std::vector<int> unordered = vertices;
  std::swap(unordered[0], unordered[1]);
  EXPECT_THROW(assemble_load_at(m, e.body_force, e.tractions, unordered), InputError);
  EXPECT_THROW(apply_stiffness_at(m, e.materials, e.stabilization, u, unordered, rows), InputError);
  const std::vector<int> outside = {0, m.num_vertices()};
  EXPECT_THROW(assemble_load_at(m, e.body_force, e.tractions, outside), InputError);
  rows.pop_back();
  EXPECT_THROW(apply_stiffness_at(m, e.materials, e.stabilization, u, vertices, rows), InputError);
}

TEST(Forces, TheLoadAndKuOfSomeVerticesAreTheWholeVectorsThere) {
  expect_the_whole_at_some_vertices<2>("paper-example-4.1-voronoi.toml", "mesh.n=8", "[0.5, -1.5]");
  expect_the_whole_at_some_vertices<3>("example-4.1-3d.toml", "mesh.n=[4, 3, 4]", "[0.5, -1.5, 2.0]");
}

// Without a load (an obstacle pushes the body) the residual is relative to the largest force.
TEST(Forces, ResidualWithoutLoad) {
  ForceBalance b;
  b.reactions.push_back({"clamped", Vec2(0.0, 2.0)});
  b.contact = Vec2(0.0, -2.0 + 1e-12);
  EXPECT_NEAR(b.residual(), 0.5e-12, 1e-16);
  EXPECT_EQ(ForceBalance().residual(), 0.0);
  b.applied = Vec2(0.0, 4.0);
  EXPECT_NEAR(b.residual(), 1.0, 1e-12);
}
