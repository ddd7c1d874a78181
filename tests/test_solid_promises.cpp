// What the plane promises and the solid must keep too: free-floating pieces refused by name,
// the same answer at every length scale and far from the origin, a negative gap refused under
// the box constraint, and the condition estimate of a nearly incompressible body.
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include "pressed_block3d.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <string>

using namespace hemivem;

namespace {

std::unique_ptr<SparseFactorization> engine() { return test::eigen_engine(); }

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

/// Example 4.1 in three dimensions at length scale s: the block s [0, 1] x [0, 0.5] x [0, 1]
/// clamped on x0 and x1, the traction (0, 0, -8) on its top, the paper's law with the box
/// constraint g = 0.02 on its bottom, Young's modulus 65 s. Stresses, pressures and
/// displacements are those of s = 1 (the stiffness grows with s, the load with s^2).
ContactProblem3D example_at_scale(const Mesh3D& mesh, double s, double poisson = 0.29) {
  return test::example_4_1_3d(mesh, s, poisson);
}

/// The mesh moved by `shift` (built by hand: the generators refuse cells this small against
/// their coordinates).
Mesh3D translated(const Mesh3D& mesh, const Vec3& shift) {
  std::vector<Vec3> vertices = mesh.vertices();
  for (Vec3& v : vertices) v += shift;
  std::vector<CellFaces> cells;
  for (int c = 0; c < mesh.num_cells(); ++c) cells.push_back(mesh.cell(c));
  return Mesh3D(vertices, cells);
}

}  // namespace

// ---- length scales ------------------------------------------------------------------------

TEST(SolidPromises, SameProblemAtEveryScaleGivesTheSamePressures) {
  ContactSolution3D reference;
  for (double s : {1.0, 1e-80, 1e-40, 1e40, 1e80, 1e100}) {
    SCOPED_TRACE("s = " + num(s));
    const Mesh3D mesh = make_cubes({4, 2, 4}, Box{0.0, s, 0.0, 0.5 * s, 0.0, s});
    const ContactProblem3D p = example_at_scale(mesh, s);
    const ContactSolution3D sol = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    ASSERT_TRUE(sol.converged()) << sol.message;
    if (s == 1.0) {
      reference = sol;
      continue;
    }
    ASSERT_EQ(sol.contact.size(), reference.contact.size());
    for (std::size_t k = 0; k < sol.contact.size(); ++k) {
      const ContactNode3D& a = sol.contact[k];
      const ContactNode3D& b = reference.contact[k];
      EXPECT_EQ(a.state, b.state) << k;
      EXPECT_NEAR(a.u_nu, b.u_nu, 1e-9 * 0.02) << k;
      EXPECT_NEAR(a.pressure(), b.pressure(), 1e-8) << k;
      EXPECT_TRUE(a.normal == b.normal) << k;
      EXPECT_NEAR(a.weight / (s * s), b.weight, 1e-14 * b.weight) << k;
    }
    EXPECT_NEAR(sol.energy / (s * s), reference.energy, 1e-9 * std::abs(reference.energy));
  }
}


// ---- far from the origin ------------------------------------------------------------------

// A tetrahedral block pressed onto a plane (uniaxial stress: an exact linear solution) and the
// same block translated along x by t. The coordinates t + x carry a round-off of eps t, which
// moves the vertices by eps t / h relative to the cell size h; the solutions may differ by a
// small multiple of that, and by nothing larger (a check relative to the coordinates' size
// instead of the cells' refuses the faces, or loses eps t / h^2).
TEST(SolidPromises, TetrahedraFarFromTheOriginSolveAsAtTheOrigin) {
  const double h = 1.0 / 3.0;
  const Box box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
  const Mesh3D mesh = make_tetrahedra({3, 3, 2}, box);
  const ContactProblem3D p = test::pressed_block(mesh, box);
  const ContactSolution3D at_origin = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  ASSERT_TRUE(at_origin.converged()) << at_origin.message;
  const double scale = at_origin.u.cwiseAbs().maxCoeff();
  for (double t : {3e7, 1e10}) {
    SCOPED_TRACE("t = " + num(t));
    const Box far{t, t + 1.0, 0.0, 1.0, 0.0, 0.5};
    const Mesh3D moved = translated(mesh, Vec3(t, 0.0, 0.0));
    const ContactProblem3D q = test::pressed_block(moved, far);
    const ContactSolution3D s = solve_contact(q, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    ASSERT_TRUE(s.converged()) << s.message;
    const double roundoff = std::numeric_limits<double>::epsilon() * t / h;
    EXPECT_LE((s.u - at_origin.u).cwiseAbs().maxCoeff(), 100.0 * roundoff * scale);
    ASSERT_EQ(s.contact.size(), at_origin.contact.size());
    for (std::size_t k = 0; k < s.contact.size(); ++k)
      EXPECT_NEAR(s.contact[k].pressure(), at_origin.contact[k].pressure(), 100.0 * roundoff * test::pressed_block_young);
  }
}

// ---- pieces no support holds ----------------------------------------------------------------

namespace {

/// Two boxes of 2 x 2 x 2 cubes side by side with a gap between them: [0, 1]^3 and
/// [2, 3] x [0, 1] x [0, 1], one mesh of two pieces.
Mesh3D two_boxes() {
  const Mesh3D a = make_cubes(2, Box{0.0, 1.0, 0.0, 1.0, 0.0, 1.0});
  std::vector<Vec3> vertices = a.vertices();
  std::vector<CellFaces> cells;
  for (int c = 0; c < a.num_cells(); ++c) cells.push_back(a.cell(c));
  const int offset = a.num_vertices();
  for (const Vec3& v : a.vertices()) vertices.push_back(v + Vec3(2.0, 0.0, 0.0));
  for (int c = 0; c < a.num_cells(); ++c) {
    CellFaces cell = a.cell(c);
    for (auto& loop : cell)
      for (int& v : loop) v += offset;
    cells.push_back(cell);
  }
  return Mesh3D(vertices, cells);
}

}  // namespace

TEST(SolidPromises, APieceNoSupportHoldsIsRefusedByName) {
  const Mesh3D mesh = two_boxes();
  ASSERT_EQ(mesh.num_cells(), 16);
  const auto held = [&](double x) { return std::abs(x) < 1e-12; };  // x = 0: the first box's side only
  const auto top = [&](const Vec3& x) { return std::abs(x.z() - 1.0) < 1e-12; };
  ContactProblem3D p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(Material{65.0, 0.3}, PlaneModel::strain);
  p.elasticity.dirichlet.push_back({select_boundary_faces(mesh, [&](const Vec3& x) { return held(x.x()); }), {}, {true, true, true}, "clamped"});
  TractionLoad3D load;
  load.facets = select_boundary_faces(mesh, top);
  load.traction = [](const Vec3&) { return Vec3(0.0, 0.0, -1.0); };
  p.elasticity.tractions.push_back(load);
  ContactPart3D contact;
  contact.name = "contact";
  contact.facets = select_boundary_faces(mesh, [](const Vec3& x) { return x.z() == 0.0 && x.x() <= 1.0; });
  contact.gap = [](const Vec3&) { return 0.01; };
  contact.law = paper_law();
  p.parts.push_back(std::move(contact));
  for (bool contact : {true, false}) {
    SCOPED_TRACE(contact ? "with contact on the first box" : "without contact");
    ContactProblem3D q = p;
    if (!contact) q.parts.clear();
    try {
      (void)solve_contact(q, engine(), *make_minimizer("ssn"), MinimizerOptions{});
      FAIL() << "the floating box was solved";
    } catch (const InputError& e) {
      const std::string what = e.what();
      // the six motions of the second box, and where it is; nothing of the first
      for (const char* motion : {"translation along x of the piece", "translation along y of the piece",
                                 "translation along z of the piece", "rotation about x of the piece",
                                 "rotation about y of the piece", "rotation about z of the piece"})
        EXPECT_NE(what.find(motion), std::string::npos) << motion << " in: " << what;
      EXPECT_NE(what.find("the piece of 8 cells in [2, 3] x [0, 1] x [0, 1]"), std::string::npos) << what;
      EXPECT_EQ(what.find("[0, 1] x [0, 1] x [0, 1]"), std::string::npos) << what;
    }
  }
  // holding the second box too: solved
  p.elasticity.dirichlet.push_back(
      {select_boundary_faces(mesh, [](const Vec3& x) { return std::abs(x.x() - 3.0) < 1e-12; }), {}, {true, true, true}, "x3"});
  const ContactSolution3D s = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
  EXPECT_TRUE(s.converged()) << s.message;
  EXPECT_LT(s.u.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LT(s.forces.residual(), 1e-8);
}

// ---- a negative gap under the box constraint ------------------------------------------------

TEST(SolidPromises, ANegativeObstacleGapUnderTheBoxConstraintIsRefusedBeforeTheEngines) {
  const Box box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};
  const Mesh3D mesh = make_cubes({2, 2, 1}, box);
  ContactProblem3D p = test::pressed_block(mesh, box);
  p.parts[0].obstacle->point = Vec3(0.0, 0.0, 0.1);  // the plane inside the block: g = -0.1
  p.parts[0].constraint = ConstraintKind::box;
  try {
    (void)solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    FAIL() << "a negative gap was solved under the box constraint";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("the box constraint |u_nu| <= g needs a finite gap >= 0, but the obstacle gives -0.1"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("contact.constraint = \"one-sided\""), std::string::npos) << what;
  }
  p.parts[0].constraint = ConstraintKind::one_sided;  // the same obstacle one-sided: solved
  EXPECT_TRUE(solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{}).converged());
}

TEST(SolidPromises, ANegativeObstacleGapInASceneNamesTheKeyAndLine) {
  const std::string text =
      "schema_version = 1\n"               // 1
      "[mesh]\n"                           // 2
      "n = [2, 2, 1]\n"                    // 3
      "domain = [0, 1, 0, 1, 0, 0.5]\n"    // 4
      "[material]\nE = 100.0\nnu = 0.3\n"  // 5-7
      "[clamped]\nside = \"top\"\n"        // 8-9
      "[contact]\n"                        // 10
      "side = \"bottom\"\n"                // 11
      "law = \"paper\"\n"                  // 12
      "constraint = \"box\"\n"             // 13
      "[contact.obstacle]\nshape = \"plane\"\npoint = [0, 0, 0.1]\nnormal = [0, 0, 1]\n";
  const Scene scene = parse_scene_string(text, "negative-gap.toml");
  try {
    (void)build_problem<3>(scene);
    FAIL() << "a negative gap was built under the box constraint";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "negative-gap.toml:13") << e.what();
    EXPECT_EQ(e.detail().rfind("contact.constraint: the box constraint |u_nu| <= g needs a finite gap >= 0", 0), 0u)
        << e.what();
  }
}

// ---- a mesh file that is not there --------------------------------------------------------

TEST(SolidPromises, AMissingGmshFileIsTheMeshFileKeysError) {
  const std::string text =
      "schema_version = 1\n"
      "[mesh]\n"
      "file = \"no-such-solid.msh\"\n"  // line 3
      "[clamped]\nside = \"x0\"\n"
      "[[loads.traction]]\nside = \"top\"\nvalue = [0.0, 0.0, -8.0]\n";
  try {
    (void)parse_scene_string(text, "missing.toml");
    FAIL() << "a scene with a missing mesh file was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "missing.toml:3") << e.what();
    EXPECT_EQ(e.detail().rfind("mesh.file: ", 0), 0u) << e.what();
    EXPECT_NE(e.detail().find("no-such-solid.msh: cannot open the mesh file"), std::string::npos) << e.what();
  }
}

// ---- the condition estimate -----------------------------------------------------------------

TEST(SolidPromises, NearlyIncompressibleBodiesReportALargeConditionEstimate) {
  const Mesh3D mesh = make_cubes({4, 2, 4}, Box{0.0, 1.0, 0.0, 0.5, 0.0, 1.0});
  std::map<double, ContactSolution3D> by_nu;
  for (double nu : {0.3, 0.4999999999999}) {
    const ContactProblem3D p = example_at_scale(mesh, 1.0, nu);
    const ContactSolution3D plain = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{});
    EXPECT_TRUE(std::isnan(plain.condition_estimate));  // not asked for
    EXPECT_TRUE(std::isnan(plain.rcond));
    const ContactSolution3D s = solve_contact(p, engine(), *make_minimizer("ssn"), MinimizerOptions{}, nullptr, true);
    ASSERT_TRUE(std::isfinite(s.condition_estimate)) << nu;
    // the margin's round-off bound grows with the estimate, and nothing else changes
    EXPECT_GE(s.uniqueness_roundoff, plain.uniqueness_roundoff) << nu;
    EXPECT_EQ(s.u, plain.u) << nu;
    by_nu[nu] = s;
  }
  constexpr double unreliable = 1e-6 / std::numeric_limits<double>::epsilon();  // app::unreliable_condition
  EXPECT_GE(by_nu[0.4999999999999].condition_estimate, unreliable);
  EXPECT_LT(by_nu[0.3].condition_estimate, 1e6);
  // without contact faces: the estimate of A
  ContactProblem3D linear = example_at_scale(mesh, 1.0, 0.4999999999999);
  linear.parts.clear();
  const ContactSolution3D s = solve_contact(linear, engine(), *make_minimizer("ssn"), MinimizerOptions{}, nullptr, true);
  EXPECT_GE(s.condition_estimate, unreliable);
}
