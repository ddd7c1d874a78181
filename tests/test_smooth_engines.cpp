// Engine-specific checks of the smoothing-based minimizers nlopt-mma and ceres-active-set
// (the shared cross-validation is tests/test_minimizers.cpp).
#include <hemivem/contact.hpp>
#include <hemivem/contact_problem.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/piecewise_law.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

using namespace hemivem;

namespace {

bool built(const std::string& name) {
  const auto names = available_minimizers();
  return std::find(names.begin(), names.end(), name) != names.end();
}

struct Example {
  Mesh mesh;
  ContactProblem problem;
  LinearSystem system;
  ContactBoundary boundary;
  std::unique_ptr<Condensation> condensation;
};

std::unique_ptr<Example> example(const std::string& kind, int n, const std::function<void(ContactProblem&)>& change = {}) {
  auto ex = std::make_unique<Example>();
  ex->mesh = make_mesh(kind, n, Rectangle{}, 5);
  ex->problem = example_4_1(ex->mesh);
  if (change) change(ex->problem);
  ex->system = assemble(ex->problem.elasticity);
  ex->boundary = make_contact_boundary(ex->mesh, ex->problem.contact_edges, ex->system.dofs, ex->problem.gap);
  FactorizationOptions fo;
  fo.engine = "eigen";
  ex->condensation = std::make_unique<Condensation>(ex->system, ex->boundary, make_factorization(fo), ex->problem.law,
                                                    ex->problem.constraint);
  return ex;
}

class SmoothEngine : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (!built(GetParam())) GTEST_SKIP() << GetParam() << " not built";
  }
  std::unique_ptr<NonsmoothMinimizer> engine() const { return make_minimizer(GetParam()); }
};

TEST_P(SmoothEngine, Diagnostics) {
  for (const std::string kind : {"squares", "voronoi"})
    for (int n : {8, 16, 32}) {
      auto ex = example(kind, n);
      const ReducedProblem& p = ex->condensation->reduced();
      MinimizerOptions o;
      o.tolerance = 1e-9;
      const MinimizerResult r = engine()->minimize(p, Eigen::VectorXd(), o);
      std::printf("%s %s N=%d size %ld: %s (%s) residual %.2e it %d f %d g %d t %.3f s\n", GetParam().c_str(), kind.c_str(), n,
                  static_cast<long>(p.size()), to_string(r.status).c_str(), r.message.c_str(), r.certificate.residual,
                  r.iterations, r.function_evaluations, r.subgradient_evaluations, r.timings.at("total"));
      for (const auto& h : r.history)
        std::printf("   %d E %.12e res %.2e act %d t %.3f\n", h.iteration, h.energy, h.residual, h.active, h.seconds);
    }
}

INSTANTIATE_TEST_SUITE_P(Engines, SmoothEngine, ::testing::Values("nlopt-mma", "ceres-active-set"), [](const auto& info) {
  std::string s = info.param;
  for (auto& c : s)
    if (c == '-') c = '_';
  return s;
});

}  // namespace
