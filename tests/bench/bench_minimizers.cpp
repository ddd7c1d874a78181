// Reduced problems of Example 4.1 on N x N squares (N1 = N - 1 contact nodes): time,
// iterations and evaluations of every built minimizer to certificate 1e-10 (or the best it
// reaches), beside one sparse factorization of the full stiffness A at the same N, in one run:
//   build/tests/bench/bench_minimizers --benchmark_counters_tabular=true
// Counters: converged (1/0), residual (certificate), iterations, evaluations (function +
// subgradient), N1.
#include <benchmark/benchmark.h>

#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/example.hpp>

#include "example_4_1.hpp"

#include <map>
#include <memory>

namespace {

using namespace hemivem;

/// The reduced problem of Example 4.1 on N x N squares, condensed once per N.
const Condensation& condensation(int n) {
  static std::map<int, std::unique_ptr<Condensation>> cache;
  auto& c = cache[n];
  if (!c) {
    const bench::Example41& ex = bench::example_4_1_on_squares(n);
    FactorizationOptions fo;
    fo.engine = available_factorizations().size() > 1 ? "cholmod" : "eigen";
    c = std::make_unique<Condensation>(ex.system, ex.boundary, make_factorization(fo), ex.problem.parts[0].law, ex.problem.parts[0].constraint);
  }
  return *c;
}

void minimize(benchmark::State& state, std::string name) {
  const Condensation& condensed = condensation(static_cast<int>(state.range(0)));
  const auto engine = make_minimizer(name);
  MinimizerOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 100000;
  MinimizerResult r;
  for (auto _ : state) r = engine->minimize(condensed.reduced(), Eigen::VectorXd(), o);
  state.counters["N1"] = static_cast<double>(condensed.reduced().size());
  state.counters["converged"] = r.converged() ? 1 : 0;
  state.counters["dual"] = r.certificate.dual;
  state.counters["iterations"] = r.iterations;
  state.counters["evaluations"] = r.function_evaluations + r.subgradient_evaluations;
}

void factorize(benchmark::State& state, std::string name) {
  const bench::Example41& s = bench::example_4_1_on_squares(static_cast<int>(state.range(0)));
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
