// Example 4.1 on N x N squares, per linear engine:
//   factorize/<engine>/N   one factorization of the full stiffness A (analysis included)
//   condense/<engine>/N    S and c (rotation, Schur complement, interior solve for c)
//   interior/<engine>/N/M  one solve with A22 (solve_interior) for M right-hand sides, after one
//                          condensation (the condition estimate's solves have 2 and 3)
// Run one case per process to read its peak memory, e.g.
//   /usr/bin/time -v build/tests/bench/bench_condensation --benchmark_filter='condense/cholmod/256$'
#include <benchmark/benchmark.h>

#include <hemivem/linear_backends.hpp>

#include "example_4_1.hpp"

#include <memory>

namespace {

using namespace hemivem;

std::unique_ptr<SparseFactorization> engine(const std::string& name) {
  FactorizationOptions o;
  o.engine = name;
  return make_factorization(o);
}

void factorize(benchmark::State& state, std::string name) {
  const bench::Example41& s = bench::example_4_1_on_squares(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    auto f = engine(name);
    const auto r = f->factorize(s.system.A);
    if (!r.ok()) state.SkipWithError(r.message.c_str());
  }
  state.counters["dofs"] = static_cast<double>(s.system.A.rows());
}

void condense(benchmark::State& state, std::string name) {
  const bench::Example41& s = bench::example_4_1_on_squares(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    Condensation c(s.system, s.boundary, engine(name), s.problem.parts[0].law, s.problem.parts[0].constraint);
    benchmark::DoNotOptimize(c.reduced().S.data());
  }
  state.counters["dofs"] = static_cast<double>(s.system.A.rows());
  state.counters["N1"] = static_cast<double>(s.boundary.size());
}

void interior(benchmark::State& state, std::string name) {
  const bench::Example41& s = bench::example_4_1_on_squares(static_cast<int>(state.range(0)));
  Condensation c(s.system, s.boundary, engine(name), s.problem.parts[0].law, s.problem.parts[0].constraint);
  const SparseFactorization& f = c.factorization();
  const Eigen::Index n2 = s.system.A.rows() - static_cast<Eigen::Index>(c.reduced().S.rows());
  const Eigen::MatrixXd B = Eigen::MatrixXd::Ones(n2, state.range(1));
  Eigen::MatrixXd X;
  for (auto _ : state) {
    const auto r = f.solve_interior(B, &X);
    if (!r.ok()) state.SkipWithError(r.message.c_str());
    benchmark::DoNotOptimize(X.data());
  }
  state.counters["dofs"] = static_cast<double>(s.system.A.rows());
}

}  // namespace

int main(int argc, char** argv) {
  for (const auto& name : available_factorizations()) {
    benchmark::RegisterBenchmark(("factorize/" + name).c_str(), factorize, name)
        ->RangeMultiplier(2)->Range(64, 512)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
    benchmark::RegisterBenchmark(("condense/" + name).c_str(), condense, name)
        ->RangeMultiplier(2)->Range(64, 512)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
    benchmark::RegisterBenchmark(("interior/" + name).c_str(), interior, name)
        ->ArgsProduct({{128, 512}, {1, 2, 3, 4}})->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
