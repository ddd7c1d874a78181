// Reduced problems as files: exact round trip, the coordinate format, and clear errors.
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/scene/example.hpp>

#include <gtest/gtest.h>

#include <limits>

#include <fstream>

#include "test_support.hpp"

using namespace hemivem;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return test::scratch("reduced-io-" + name); }

void write(const fs::path& f, const std::string& text) {
  fs::create_directories(f.parent_path());
  std::ofstream(f) << text;
}

void expect_error(const fs::path& folder, const std::string& fragment) {
  try {
    read_reduced_problem(folder);
    FAIL() << "expected InputError containing '" << fragment << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(ReducedIo, Example41RoundTripIsExact) {
  const Mesh mesh = make_squares(8);
  const ContactProblem cp = example_4_1(mesh);
  const LinearSystem sys = assemble(cp.elasticity);
  const ContactBoundary cb = make_contact_boundary(mesh, cp.parts[0].facets, sys.dofs, cp.parts[0].gap);
  FactorizationOptions fo;
  const Condensation cond(sys, cb, make_factorization(fo), cp.parts[0].law, cp.parts[0].constraint);
  const fs::path dir = scratch("example");
  write_reduced_problem(dir, cond.reduced());
  const ReducedProblem q = read_reduced_problem(dir);
  const ReducedProblem& p = cond.reduced();
  EXPECT_EQ((q.S - p.S).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(q.c, p.c);
  EXPECT_EQ(q.w, p.w);
  EXPECT_EQ(q.uniform_form()->g, p.uniform_form()->g);
  EXPECT_EQ(q.uniform_form()->constraint, p.uniform_form()->constraint);
  EXPECT_EQ(q.uniqueness_margin, p.uniqueness_margin);
  EXPECT_EQ(q.law_by_number(0).name(), "paper");
  for (double r = -0.01; r < 0.05; r += 0.0013) EXPECT_EQ(q.law_by_number(0).value(r), p.law_by_number(0).value(r));
  EXPECT_EQ(q.law_by_number(0).alpha(), 20.0);
  for (const auto& f : fs::directory_iterator(dir)) EXPECT_NE(f.path().extension(), ".part");
  // a law given by name replaces law.txt
  fs::remove(dir / "law.txt");
  EXPECT_EQ(read_reduced_problem(dir, zero_law()).law_by_number(0).name(), "zero");
  fs::remove_all(dir);
}

TEST(ReducedIo, CoordinateFormatAndDefaults) {
  const fs::path dir = scratch("coordinate");
  write(dir / "S.mtx", "%%MatrixMarket matrix coordinate real symmetric\n% a comment\n2 2 3\n1 1 4\n2 1 -1\n2 2 3\n");
  write(dir / "c.txt", "1\n2\n");
  write(dir / "w.txt", "0.5\n0.5\n");
  write(dir / "g.txt", "0.1\n0.1\n");
  write(dir / "law.txt", "name kinked\nbreakpoints 0\nj1 0\nj2 0\nj1 0 0.3 50\nj2 0\n");
  const ReducedProblem p = read_reduced_problem(dir);
  EXPECT_EQ(p.S(1, 0), -1.0);
  EXPECT_EQ(p.S(0, 1), -1.0);
  EXPECT_EQ(p.S(1, 1), 3.0);
  EXPECT_EQ(p.uniform_form()->constraint, ConstraintKind::box);  // no problem.txt: the paper's box
  // no margin in the folder: it is computed, lambda_min(S - alpha W) with W = 0.5 I, whose
  // exact value is (7 - sqrt(5)) / 2 - alpha / 2
  EXPECT_NEAR(p.uniqueness_margin, (7.0 - std::sqrt(5.0)) / 2.0 - 0.5 * p.law_by_number(0).alpha(), 1e-14);
  EXPECT_EQ(p.law_by_number(0).derivative(LawPart::j, 0.0, +1), 0.3);
  fs::remove_all(dir);
}

/// A valid problem of size 2 in `dir`, over whatever was there.
void write_valid_problem(const fs::path& dir) {
  write(dir / "S.mtx", "%%MatrixMarket matrix array real general\n2 2\n1\n0\n0\n1\n");
  write(dir / "c.txt", "1\n2\n");
  write(dir / "w.txt", "1\n1\n");
  write(dir / "g.txt", "0.1\n0.1\n");
  write(dir / "law.txt", "name zero\nbreakpoints\nj1 0\nj2 0\n");
  fs::remove(dir / "problem.txt");
}

/// One file of a valid problem replaced by `text`, and the fragment of the error reading the
/// folder must give.
struct Defect {
  const char* file;
  const char* text;
  const char* fragment;
};

const Defect kDefects[] = {
    {"S.mtx", "%%MatrixMarket matrix array real general\n2 2\n1\n0\n0.5\n1\n", "S is not symmetric"},
    {"c.txt", "1\n", "c.txt: has 1 numbers; S is 2 x 2"},
    {"c.txt", "1\nnan\n", "c.txt:2: c 'nan' is not finite"},
    {"g.txt", "0.1\n-1\n", "g.txt: entry 2: gap -1 must be finite and >= 0 with the box constraint"},
    {"g.txt", "0.1\ninf\n", "g.txt: entry 2: gap inf must be finite and >= 0 with the box constraint"},
    {"g.txt", "0.1\n-inf\n", "g.txt:2: g '-inf' is not finite"},
    {"S.mtx", "%%MatrixMarket matrix array complex general\n2 2\n1\n0\n0\n1\n", "S.mtx:1: unsupported Matrix Market header"},
    {"S.mtx", "%%MatrixMarket matrix array real general\n2 2\n1\n0\n0\n", "S.mtx:2: expected 4 entries after the size line, found 3"},
    {"S.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 1\n", "S.mtx:3: entry (3, 1) outside the 2 x 2 matrix"},
    {"law.txt", "name bad\nbreakpoints 0\nj1 0\nj2 0\nj1 1\nj2 0\n", "j1 is not continuous at breakpoint 0"},
    {"law.txt", "name zero\nbreakpoints\nj1 0\nj2 0\nslope 3\n", "law.txt:5: unknown key 'slope'"},
    {"problem.txt", "constraint two-sided\n", "problem.txt:1: unknown constraint 'two-sided'"},
};

TEST(ReducedIo, DefectsNameTheFileAndLine) {
  const fs::path dir = scratch("defects");
  write_valid_problem(dir);
  EXPECT_NO_THROW(read_reduced_problem(dir));
  for (const Defect& d : kDefects) {
    SCOPED_TRACE(std::string(d.file) + ": " + d.fragment);
    write_valid_problem(dir);
    write(dir / d.file, d.text);
    expect_error(dir, d.fragment);
  }
  {
    // one-sided: an obstacle pressed in (g < 0) and a node that cannot touch it (g = inf)
    write_valid_problem(dir);
    write(dir / "g.txt", "-0.5\ninf\n");
    write(dir / "problem.txt", "constraint one-sided\n");
    const ReducedProblem p = read_reduced_problem(dir);
    EXPECT_EQ(p.uniform_form()->g(0), -0.5);
    EXPECT_EQ(p.uniform_form()->g(1), std::numeric_limits<double>::infinity());
    fs::remove(dir / "problem.txt");
  }
  write_valid_problem(dir);
  write(dir / "problem.txt", "format 2\nconstraint box\n");
  fs::remove(dir / "c.txt");
  expect_error(dir, "cannot open the file");
  fs::remove_all(dir);
  expect_error(dir, "not a folder");
}

}  // namespace
