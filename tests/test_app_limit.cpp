// The limit of hemivem::app (app/limit.hpp): the plain Q1 matrices against the energy of an
// affine displacement and the sparsity of the VEM matrix, a measurement on a small plane and a
// small solid against the mesh's counts and its own numbers, and the refusals with their keys.
#include <gtest/gtest.h>

#include <hemivem/app/limit.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "test_support.hpp"

namespace hemivem::app {
namespace {

bool cholmod_built() {
  const auto built = available_factorizations();
  return std::find(built.begin(), built.end(), "cholmod") != built.end();
}


/// u^T K u for K given by its lower triangle.
double energy_of_lower(const SparseMatrix& lower, const Eigen::VectorXd& u) {
  const Eigen::VectorXd Lu = lower * u;
  const Eigen::VectorXd LTu = lower.transpose() * u;
  return u.dot(Lu) + u.dot(LTu) - u.dot(lower.diagonal().cwiseProduct(u));
}

/// The stored entries of a lower triangle, as (row, col) pairs in column order.
std::vector<std::pair<int, int>> pattern_of(const SparseMatrix& lower) {
  std::vector<std::pair<int, int>> p;
  for (int c = 0; c < lower.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(lower, c); it; ++it) p.emplace_back(static_cast<int>(it.row()), c);
  return p;
}

Scene plane(int n) {
  Scene s = default_scene();
  apply_overrides(s, {"mesh.n=" + std::to_string(n)});
  return s;
}

Scene solid() {
  Scene s = parse_scene(hemivem::test::scenes_dir() / "example-4.1-3d.toml");
  apply_overrides(s, {"mesh.domain=[0,1,0,1,0,1]"});
  return s;
}

// Q1 is exact on affine fields: u^T K u of u = (a x + c y, d x + b y) is the integral of
// sigma : eps = lambda (tr eps)^2 + 2 mu eps : eps, and K annihilates the rigid motions.
TEST(AppLimit, PlainQ1MatrixOfSquaresIsExactOnAffineFields) {
  const Mesh mesh = make_squares(GridSize(4, 3), Rectangle{0.0, 2.0, 0.0, 1.5});
  const DofMap dofs = make_dof_map(mesh, {});
  const double lambda = 1.7, mu = 0.6;
  const SparseMatrix K = plain_q1_matrix(mesh, dofs, lambda, mu);
  ASSERT_EQ(K.rows(), 2 * mesh.num_vertices());
  const double a = 0.3, b = -0.2, c = 0.5, d = 0.1;
  Eigen::VectorXd u(2 * mesh.num_vertices()), rotation(2 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec2 x = mesh.vertex(v);
    u(dofs.free_index(2 * v)) = a * x.x() + c * x.y();
    u(dofs.free_index(2 * v + 1)) = d * x.x() + b * x.y();
    rotation(dofs.free_index(2 * v)) = -x.y();
    rotation(dofs.free_index(2 * v + 1)) = x.x();
  }
  const double shear = 0.5 * (c + d);
  const double exact = 3.0 * (lambda * (a + b) * (a + b) + 2 * mu * (a * a + b * b + 2 * shear * shear));
  EXPECT_NEAR(energy_of_lower(K, u), exact, 1e-12 * exact);
  EXPECT_NEAR(energy_of_lower(K, rotation), 0.0, 1e-13 * (lambda + 2 * mu) * rotation.squaredNorm());
}

TEST(AppLimit, PlainQ1MatrixOfBoxesIsExactOnAffineFields) {
  const Mesh3D mesh = make_cubes(GridSize3(2, 3, 2), Box{0.0, 1.0, 0.0, 1.5, 0.0, 0.5});
  const DofMap dofs = make_dof_map(mesh, std::vector<DirichletCondition3D>{});
  const double lambda = 1.2, mu = 0.8;
  const SparseMatrix K = plain_q1_matrix(mesh, dofs, lambda, mu);
  ASSERT_EQ(K.rows(), 3 * mesh.num_vertices());
  Eigen::Matrix3d G;  // the displacement's gradient
  G << 0.3, 0.1, -0.2, 0.4, -0.1, 0.2, 0.0, 0.5, 0.25;
  Eigen::VectorXd u(3 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 y = G * mesh.vertex(v);
    for (int k = 0; k < 3; ++k) u(dofs.free_index(3 * v + k)) = y(k);
  }
  const Eigen::Matrix3d eps = 0.5 * (G + G.transpose());
  const double exact = 0.75 * (lambda * eps.trace() * eps.trace() + 2 * mu * eps.squaredNorm());
  EXPECT_NEAR(energy_of_lower(K, u), exact, 1e-12 * exact);
}

// "The same sparsity as the VEM matrix": the lower triangles of the two hold the same entries.
TEST(AppLimit, PlainQ1MatrixHasTheSparsityOfTheVemMatrix) {
  {
    const auto built = build_problem(plane(6));
    const auto& elasticity = built->problem.elasticity;
    const LinearSystem vem = assemble(elasticity);
    const SparseMatrix q1 = plain_q1_matrix(built->mesh, make_dof_map(built->mesh, elasticity.dirichlet), 1.0, 1.0);
    const SparseMatrix lower = vem.A.triangularView<Eigen::Lower>();
    EXPECT_EQ(pattern_of(q1), pattern_of(lower));
  }
  {
    Scene s = solid();
    apply_overrides(s, {"mesh.n=3"});
    const auto built = build_problem<3>(s);
    const auto& elasticity = built->problem.elasticity;
    const LinearSystem vem = assemble(elasticity);
    const SparseMatrix q1 = plain_q1_matrix(built->mesh, make_dof_map(built->mesh, elasticity.dirichlet), 1.0, 1.0);
    const SparseMatrix lower = vem.A.triangularView<Eigen::Lower>();
    EXPECT_EQ(pattern_of(q1), pattern_of(lower));
  }
}

TEST(AppLimit, PlainQ1MatrixRefusesOtherElements) {
  const Mesh triangles = make_triangles(GridSize(2, 2));
  EXPECT_EQ(test::input_error_key([&] { (void)plain_q1_matrix(triangles, make_dof_map(triangles, {}), 1.0, 1.0); }),
            "mesh.generator");
  const Mesh3D tets = make_tetrahedra(GridSize3(1, 1, 1));
  EXPECT_EQ(test::input_error_key([&] {
              (void)plain_q1_matrix(tets, make_dof_map(tets, std::vector<DirichletCondition3D>{}), 1.0, 1.0);
            }),
            "mesh.generator");
}

/// What every row of a measurement holds, whatever the machine's speed: the numbers of its
/// mesh, a converged solve, positive times and the ratios of its own numbers.
void expect_consistent(const LimitRow& row) {
  EXPECT_EQ(row.status, "converged");
  double staged = 0.0;  // the stages of the solve up to result.json
  for (const char* k : {"mesh", "setup", "assembly", "condensation", "condition", "minimize", "back_substitution",
                        "post_process", "release", "estimate", "result_json", "margin", "outputs"}) {
    ASSERT_TRUE(row.stage.count(k)) << k;
    EXPECT_GE(row.stage.at(k), 0.0) << k;
    if (std::string(k) != "margin" && std::string(k) != "outputs") staged += row.stage.at(k);
  }
  EXPECT_GT(row.stage.at("condensation"), 0.0);
  EXPECT_GT(row.stage.at("condition"), 0.0) << "a solve of the command estimates the condition";
  EXPECT_GT(row.stage.at("estimate"), 0.0);
  EXPECT_GT(row.stage.at("release"), 0.0) << "the solver and its factorization are given back in the solve";
  EXPECT_LE(staged, row.solve) << "the stages are parts of the solve's wall time";
  EXPECT_GT(row.solve, 0.0);
  EXPECT_GT(row.plain_assembly, 0.0);
  EXPECT_GT(row.factorization, 0.0);
  EXPECT_TRUE(row.ordering == "amd" || row.ordering == "metis") << row.ordering;
  ASSERT_EQ(row.alternative.size(), 1u);
  // the ordering kept is the faster of the two
  EXPECT_LE(row.analysis + row.factorization, row.alternative.begin()->second);
  EXPECT_NE(row.alternative.begin()->first, row.ordering);
  EXPECT_GT(row.factor_bytes, 0.0);
  EXPECT_GT(row.peak_rss, row.matrix_bytes);
  const double factor = row.analysis + row.factorization;
  const std::vector<LimitRatio> ratios = limit_ratios(row);
  ASSERT_EQ(ratios.size(), 7u);
  EXPECT_EQ(ratios[0].key, "solve_over_limit");
  EXPECT_DOUBLE_EQ(ratios[0].value, row.solve / (row.plain_assembly + factor));
  EXPECT_DOUBLE_EQ(ratios[2].value, row.stage.at("assembly") / row.plain_assembly);
  EXPECT_DOUBLE_EQ(ratios[3].value, row.stage.at("condensation") / factor);
  const nlohmann::json j = limit_row_json(row);
  EXPECT_EQ(j["ratios"].size(), ratios.size());
  for (const LimitRatio& q : ratios) EXPECT_DOUBLE_EQ(j["ratios"][q.key].get<double>(), q.value) << q.key;
  EXPECT_DOUBLE_EQ(j["limit"]["factorization"].get<double>(), row.factorization);
}

TEST(AppLimit, MeasuresAPlaneRowBySizeInFreshProcesses) {
  if (!cholmod_built()) GTEST_SKIP() << "the cholmod engine was not built";
  LimitOptions o;
  o.sizes = {8, 4, 8};
  o.repeat = 2;
  std::vector<int> started, done;
  o.size_started = [&](int n) { started.push_back(n); };
  o.size_done = [&](const LimitRow& r) { done.push_back(r.n); };
  // A's nonzeros at each size, assembled here first: the caller has run OpenMP's parallel
  // regions before the measurement forks
  std::map<int, double> nonzeros;
  for (int n : {4, 8}) nonzeros[n] = static_cast<double>(assemble(build_problem(plane(n))->problem.elasticity).A.nonZeros());
  const LimitResult r = run_limit(plane(16), o);
  EXPECT_EQ(r.plan.base.solver.linear, "cholmod");
  EXPECT_EQ(r.plan.options.sizes, (std::vector<int>{4, 8}));
  EXPECT_EQ(started, (std::vector<int>{4, 8}));
  EXPECT_EQ(done, started);
  ASSERT_EQ(r.rows.size(), 2u);
  for (const LimitRow& row : r.rows) {
    // Example 4.1: x = 0 and x = 1 clamped, every other dof free; the contact nodes off them
    EXPECT_EQ(row.dofs, 2 * (row.n + 1) * (row.n - 1)) << row.n;
    EXPECT_EQ(row.contact_nodes, row.n - 1) << row.n;
    // A's storage: both triangles' values and row indices, and its column starts
    EXPECT_DOUBLE_EQ(row.matrix_bytes, 12.0 * nonzeros.at(row.n) + 4.0 * (row.dofs + 1));
    expect_consistent(row);
  }
  const nlohmann::json j = limit_json(r);
  EXPECT_EQ(j["schema"], "hemivem-bench-limit/4");
  EXPECT_EQ(j["linear"], "cholmod");
  EXPECT_EQ(j["minimizer"], r.plan.base.solver.minimizer);
  EXPECT_EQ(j["repeat"], 2);
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["rows"][1]["n"], 8);
  EXPECT_EQ(j["rows"][1]["dofs"], 2 * 9 * 7);
}

TEST(AppLimit, MeasuresASolidAgainstItsBoxes) {
  if (!cholmod_built()) GTEST_SKIP() << "the cholmod engine was not built";
  LimitOptions o;
  o.sizes = {3};
  const LimitResult r = run_limit(solid(), o);
  ASSERT_EQ(r.rows.size(), 1u);
  const LimitRow& row = r.rows[0];
  // 3^3 boxes, x = 0 and x = 1 clamped: 3 (n + 1)^2 (n - 1) dofs; the bottom's nodes off them
  EXPECT_EQ(row.dofs, 3 * 4 * 4 * 2);
  EXPECT_EQ(row.contact_nodes, 4 * 2);
  expect_consistent(row);
}

TEST(AppLimit, RefusesWhatItCannotMeasureAtItsKey) {
  if (!cholmod_built()) {
    EXPECT_EQ(test::input_error_key([] { (void)plan_limit(plane(8), {}); }), "limit");
    return;
  }
  Scene voronoi = plane(8);
  apply_overrides(voronoi, {"mesh.generator=\"voronoi\""});
  EXPECT_EQ(test::input_error_key([&] { (void)plan_limit(voronoi, {}); }), "mesh.generator");
  Scene tets = solid();
  apply_overrides(tets, {"mesh.generator=\"tetrahedra\""});
  EXPECT_EQ(test::input_error_key([&] { (void)plan_limit(tets, {}); }), "mesh.generator");
  LimitOptions o;
  o.repeat = 0;
  EXPECT_EQ(test::input_error_key([&] { (void)plan_limit(plane(8), o); }), "repeat");
  o = {};
  o.sizes = {4, 0};
  EXPECT_EQ(test::input_error_key([&] { (void)plan_limit(plane(8), o); }), "n");
  o.keys.sizes = "--n";
  EXPECT_EQ(test::input_error_key([&] { check_limit_options(o); }), "--n");
  o = {};
  o.sizes = {1000000};
  EXPECT_EQ(test::input_error_key([&] { (void)plan_limit(plane(8), o); }), "n");  // beyond the memory
}

TEST(AppLimit, DefaultSizesByDimension) {
  EXPECT_EQ(limit_default_sizes(2), (std::vector<int>{128, 256, 512}));
  EXPECT_EQ(limit_default_sizes(3), (std::vector<int>{16, 24, 32}));
  if (!cholmod_built()) GTEST_SKIP() << "the cholmod engine was not built";
  EXPECT_EQ(plan_limit(plane(8), {}).options.sizes, limit_default_sizes(2));
  const LimitPlan p = plan_limit(solid(), {});
  EXPECT_EQ(p.options.sizes, limit_default_sizes(3));
  ASSERT_EQ(p.scenes.size(), 3u);
  EXPECT_EQ(p.scenes[2].mesh.cells3().nx, 32);
}

}  // namespace
}  // namespace hemivem::app
