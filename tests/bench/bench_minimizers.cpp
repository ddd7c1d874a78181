// Reduced problems of Example 4.1 on N x N squares (N1 = N - 1 contact nodes): time,
// iterations and evaluations of every built minimizer to certificate 1e-10 (or the best it
// reaches), beside one sparse factorization of the full stiffness A at the same N, in one run:
//   build/tests/bench/bench_minimizers --benchmark_counters_tabular=true
// Counters: converged (1/0), residual (certificate), iterations, evaluations (function +
// subgradient), N1.
#include <benchmark/benchmark.h>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/example.hpp>

#include <map>
#include <memory>

namespace {

using namespace hemivem;

struct Setup {
  Mesh mesh;
  ContactProblem problem;
  LinearSystem system;
  std::unique_ptr<Condensation> condensation;
};

const Setup& setup(int n) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[n];
  if (!s) {
    s = std::make_unique<Setup>();
    s->mesh = make_squares(n);
    s->problem = example_4_1(s->mesh);
    s->system = assemble(s->problem.elasticity);
    const ContactBoundary cb = make_contact_boundary(s->mesh, s->problem.contact_edges, s->system.dofs, s->problem.gap);
    FactorizationOptions fo;
    fo.engine = available_factorizations().size() > 1 ? "cholmod" : "eigen";
    s->condensation = std::make_unique<Condensation>(s->system, cb, make_factorization(fo), s->problem.law, s->problem.constraint);
  }
  return *s;
}

void minimize(benchmark::State& state, std::string name) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  const auto engine = make_minimizer(name);
  MinimizerOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 100000;
  MinimizerResult r;
  for (auto _ : state) r = engine->minimize(s.condensation->reduced(), Eigen::VectorXd(), o);
  state.counters["N1"] = static_cast<double>(s.condensation->reduced().size());
  state.counters["converged"] = r.converged() ? 1 : 0;
  state.counters["dual"] = r.certificate.dual;
  state.counters["iterations"] = r.iterations;
  state.counters["evaluations"] = r.function_evaluations + r.subgradient_evaluations;
}

void factorize(benchmark::State& state, std::string name) {
  const Setup& s = setup(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    FactorizationOptions fo;
    fo.engine = name;
    auto f = make_factorization(fo);
    if (!f->factorize(s.system.A).ok()) state.SkipWithError("factorization failed");
  }
  state.counters["dofs"] = static_cast<double>(s.system.A.rows());
}

}  // namespace

int main(int argc, char** argv) {
  for (const auto& name : available_minimizers())
    benchmark::RegisterBenchmark(("minimize/" + name).c_str(), minimize, name)
        ->RangeMultiplier(2)->Range(32, 512)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.2);
  for (const std::string name : {"cholmod", "eigen"}) {
    const auto built = available_factorizations();
    if (std::find(built.begin(), built.end(), name) == built.end()) continue;
    benchmark::RegisterBenchmark(("factorize/" + name).c_str(), factorize, name)
        ->RangeMultiplier(2)->Range(32, 512)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
