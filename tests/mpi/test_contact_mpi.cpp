// solve_contact with the MPI MUMPS engine: every process runs the pipeline, the engine's calls
// are collective, the minimizer and the results belong to rank 0 (hemivem/contact_solver.hpp).
//
// Rank 0 compares its results with the Eigen engine's in one process; the other ranks check
// that they received the shared status and nothing else. Failures of the minimizer on rank 0
// must reach every process (a process left waiting in a collective call would hang the test
// until its CTest timeout). main() reduces the outcome over all processes.
#include <hemivem/contact/solver.hpp>
#include <hemivem/eigen_factorization.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/minimizer_run.hpp>
#include <hemivem/mumps_mpi_factorization.hpp>
#include <hemivem/process_group.hpp>
#include <hemivem/ssn_minimizer.hpp>
#include <hemivem/scene/example.hpp>

#include <gtest/gtest.h>
#include <mpi.h>

#include "mpi_test_main.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace {

using namespace hemivem;

int rank() { return MumpsMpiFactorization::mpi_rank(); }
bool root() { return rank() == 0; }

std::unique_ptr<SparseFactorization> mpi_engine() { return std::make_unique<MumpsMpiFactorization>(); }

MinimizerOptions tight() {
  MinimizerOptions o;
  o.tolerance = 1e-10;
  return o;
}

/// Runs rank 0's minimizer as given; throws or stops early on request.
class Scripted final : public NonsmoothMinimizer {
 public:
  enum class Mode { ssn, throw_input, throw_runtime, iteration_limit };
  explicit Scripted(Mode mode) : mode_(mode) {}
  std::string name() const override { return "scripted"; }
  mutable int calls = 0;

 protected:
  MinimizerResult run(MinimizerRun& r) const override {
    const ReducedProblem& p = r.problem();
    const Eigen::VectorXd& start = r.start();
    const MinimizerOptions& o = r.options();
    ++calls;
    switch (mode_) {
      case Mode::throw_input: throw InputError("scripted input error", "minimizer");
      case Mode::throw_runtime: throw std::runtime_error("scripted runtime error");
      case Mode::iteration_limit: {
        MinimizerOptions one = o;
        one.max_iterations = 1;
        MinimizerResult r = SsnMinimizer{}.minimize(p, start, one);
        EXPECT_FALSE(r.converged());
        return r;
      }
      case Mode::ssn: break;
    }
    return SsnMinimizer{}.minimize(p, start, o);
  }

 private:
  Mode mode_;
};

TEST(ContactMpi, Example41MatchesEigenOnRankZero) {
  const Mesh mesh = make_squares(16);
  const ContactProblem p = example_4_1(mesh);
  Scripted ssn(Scripted::Mode::ssn);
  ReducedProblem reduced;
  const ContactSolution s = solve_contact(p, mpi_engine(), ssn, tight(), &reduced);
  EXPECT_TRUE(s.converged());
  EXPECT_EQ(s.stages, (std::vector<std::string>{"assembly", "condensation", "minimize", "back_substitution"}));
  EXPECT_EQ(s.unknowns, 2 * 17 * 15);
  if (root()) {
    EXPECT_EQ(ssn.calls, 1);
    const ContactSolution e =
        solve_contact(p, std::make_unique<EigenFactorization>(), SsnMinimizer{}, tight());
    ASSERT_EQ(s.u.size(), e.u.size());
    EXPECT_LE((s.u - e.u).lpNorm<Eigen::Infinity>(), 1e-10 * e.u.lpNorm<Eigen::Infinity>());
    ASSERT_EQ(s.contact.size(), e.contact.size());
    for (std::size_t i = 0; i < s.contact.size(); ++i) {
      EXPECT_EQ(s.contact[i].vertex, e.contact[i].vertex);
      EXPECT_EQ(s.contact[i].state, e.contact[i].state);
      EXPECT_NEAR(s.contact[i].u_nu, e.contact[i].u_nu, 1e-12);
    }
    EXPECT_NEAR(s.energy, e.energy, 1e-10 * std::abs(e.energy));
    EXPECT_NEAR(s.uniqueness_margin, e.uniqueness_margin, 1e-8 * e.uniqueness_margin);
    EXPECT_EQ(reduced.size(), 15);
  } else {
    EXPECT_EQ(ssn.calls, 0);  // the reduced problem is solved on rank 0 only
    EXPECT_EQ(s.u.size(), 0);
    EXPECT_TRUE(s.contact.empty());
    EXPECT_EQ(reduced.S.size(), 0);
  }
}

TEST(ContactMpi, NoContactBoundaryIsOneCollectiveLinearSolve) {
  const Mesh mesh = make_squares(8);
  ContactProblem p = example_4_1(mesh);
  p.parts.clear();
  Scripted unused(Scripted::Mode::ssn);
  const ContactSolution s = solve_contact(p, mpi_engine(), unused, tight());
  EXPECT_EQ(unused.calls, 0);
  EXPECT_TRUE(s.converged());
  EXPECT_EQ(s.stages, (std::vector<std::string>{"assembly", "linear_solve"}));
  if (root()) {
    const ContactSolution e = solve_contact(p, std::make_unique<EigenFactorization>(), unused, tight());
    ASSERT_EQ(s.u.size(), e.u.size());
    EXPECT_LE((s.u - e.u).lpNorm<Eigen::Infinity>(), 1e-10 * e.u.lpNorm<Eigen::Infinity>());
    EXPECT_NEAR(s.energy, e.energy, 1e-10 * std::abs(e.energy));
  } else {
    EXPECT_EQ(s.u.size(), 0);
  }
}

TEST(ContactMpi, NotConvergedOnRankZeroIsTheStatusEverywhere) {
  const Mesh mesh = make_squares(16);
  const ContactProblem p = example_4_1(mesh);
  Scripted limited(Scripted::Mode::iteration_limit);
  const ContactSolution s = solve_contact(p, mpi_engine(), limited, tight());
  EXPECT_FALSE(s.converged());
  EXPECT_EQ(s.status, MinimizerStatus::iteration_limit);
  EXPECT_EQ(s.stages.back(), "back_substitution");
}

TEST(ContactMpi, InputErrorOfTheMinimizerReachesEveryProcess) {
  const Mesh mesh = make_squares(8);
  const ContactProblem p = example_4_1(mesh);
  Scripted failing(Scripted::Mode::throw_input);
  try {
    solve_contact(p, mpi_engine(), failing, tight());
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (root())
      EXPECT_NE(what.find("scripted input error"), std::string::npos) << what;
    else
      EXPECT_NE(what.find("process holding the results"), std::string::npos) << what;
  }
  // Every process left the failed solve at the same point: the next collective run works.
  Scripted ssn(Scripted::Mode::ssn);
  EXPECT_TRUE(solve_contact(p, mpi_engine(), ssn, tight()).converged());
}

TEST(ContactMpi, OtherFailuresOfTheMinimizerReachEveryProcess) {
  const Mesh mesh = make_squares(8);
  const ContactProblem p = example_4_1(mesh);
  Scripted failing(Scripted::Mode::throw_runtime);
  if (root()) {
    EXPECT_THROW(solve_contact(p, mpi_engine(), failing, tight()), std::runtime_error);
  } else {
    EXPECT_THROW(solve_contact(p, mpi_engine(), failing, tight()), hemivem::Error);
  }
  Scripted ssn(Scripted::Mode::ssn);
  EXPECT_TRUE(solve_contact(p, mpi_engine(), ssn, tight()).converged());
}

TEST(ContactMpi, WorkWhereTheResultsAreEndsAlikeOnEveryProcess) {
  const MumpsMpiFactorization engine;
  int ran = 0;
  engine.run_where_results_are([&] { ++ran; });
  EXPECT_EQ(ran, root() ? 1 : 0) << "the work runs on rank 0 only";
  try {
    engine.run_where_results_are([] { throw NumericalError("scripted numerical error"); });
    ADD_FAILURE() << "no exception";
  } catch (const NumericalError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(root() ? "scripted numerical error" : "process holding the results"), std::string::npos)
        << what;
  }
}

TEST(ContactMpi, AWrongSizeForTheBackSubstitutionIsAnInputErrorEverywhere) {
  const Mesh mesh = make_squares(8);
  const ContactProblem p = example_4_1(mesh);
  const LinearSystem sys = assemble(p.elasticity);
  const ContactBoundary boundary = contact_boundary(p, sys.dofs);
  const Condensation cond(sys, boundary, mpi_engine(), p.parts[0].law, constraint_in_effect(p.parts[0]));
  EXPECT_THROW(cond.back_substitute(Eigen::VectorXd::Zero(boundary.size() + 1)), InputError);
  // every process left at the same point: a back-substitution of the right size works
  const Eigen::VectorXd u = cond.back_substitute(Eigen::VectorXd::Zero(boundary.size()));
  EXPECT_EQ(u.size(), root() ? 2 * mesh.num_vertices() : 0);
}

TEST(ContactMpi, EngineReportsWhereTheResultsAre) {
  const MumpsMpiFactorization engine;
  EXPECT_EQ(engine.holds_results(), root());
  EXPECT_EQ(engine.num_processes(), MumpsMpiFactorization::mpi_size());
  EXPECT_EQ(engine.share(root() ? 17 : -rank()), 17);
  const ProcessGroup& processes = processes_of(engine);
  EXPECT_EQ(&processes, static_cast<const ProcessGroup*>(&engine));
  EXPECT_EQ(processes.share(root() ? 23 : -rank()), 23);
  EXPECT_EQ(processes_of(EigenFactorization()).num_processes(), 1) << "an engine in one process on every rank";
}

}  // namespace

int main(int argc, char** argv) { return hemivem::test::run_tests_on_every_rank(argc, argv, "solve_contact with mumps-mpi"); }
