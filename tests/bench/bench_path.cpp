// Loading histories against one static solve (docs/paths.md), Example 4.1 on N x N squares
// with the CHOLMOD engine and ssn:
//   solve/N              one static solve (assembly, condensation, minimizer, back-substitution)
//   path/N/K             a proportional path of K steps (t_k = k/K), the last step's displacement
//   path-tresca/N/K      the same with Tresca friction (g = 0.8, top traction (3, -8))
//   path-coulomb/N/K     Coulomb friction (mu = 0.3): a fixed point in every step (its one solve:
//                        the one-step path t = 1; the counter tresca_per_step)
// Each path reports the counter `solves`: its time over the static solve's of the same N
// measured in the same run (the target is at most 2 at N = 256, K = 1000).
//   build/tests/bench/bench_path --benchmark_filter='/256'
#include <benchmark/benchmark.h>

#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/scene/example.hpp>

#include <chrono>
#include <map>
#include <memory>

namespace {

using namespace hemivem;

std::unique_ptr<SparseFactorization> cholmod() {
  FactorizationOptions o;
  o.engine = available_factorizations().front() == "eigen" ? "eigen" : "cholmod";
  for (const auto& name : available_factorizations())
    if (name == "cholmod") o.engine = name;
  return make_factorization(o);
}

enum class Kind { frictionless, tresca, coulomb };

ContactProblem problem_of(const Mesh& mesh, Kind kind) {
  ContactProblem p = example_4_1(mesh);
  if (kind == Kind::frictionless) return p;
  p.elasticity.tractions[0].traction = [](const Vec2&) { return Vec2(3.0, -8.0); };
  if (kind == Kind::tresca) {
    p.parts[0].friction = tresca_law(0.8);
  } else {
    p.parts[0].friction = tresca_law(1.0);
    p.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 0.3, {}};
  }
  return p;
}

const Mesh& mesh_of(int n) {
  static std::map<int, Mesh> meshes;
  auto it = meshes.find(n);
  if (it == meshes.end()) it = meshes.emplace(n, make_squares(n)).first;
  return it->second;
}

// seconds of one static solve per (N, kind), measured once in this run
std::map<std::pair<int, int>, double>& static_seconds() {
  static std::map<std::pair<int, int>, double> s;
  return s;
}

double solve_once(int n, Kind kind) {
  const ContactProblem p = problem_of(mesh_of(n), kind);
  const auto minimizer = make_minimizer("ssn");
  const auto t0 = std::chrono::steady_clock::now();
  if (kind == Kind::coulomb) {  // the static Coulomb problem is the one-step path t = 1
    ContactProblem q = p;
    const PathSolution s = solve_path(q, cholmod(), *minimizer, PathLoading{{1.0}, {}});
    benchmark::DoNotOptimize(s.last.u.data());
  } else {
    const ContactSolution s = solve_contact(p, cholmod(), *minimizer, MinimizerOptions{});
    benchmark::DoNotOptimize(s.u.data());
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void solve(benchmark::State& state, Kind kind) {
  const int n = static_cast<int>(state.range(0));
  double seconds = 0.0;
  for (auto _ : state) seconds = solve_once(n, kind);
  static_seconds()[{n, static_cast<int>(kind)}] = seconds;
}

void path(benchmark::State& state, Kind kind) {
  const int n = static_cast<int>(state.range(0)), K = static_cast<int>(state.range(1));
  std::vector<double> t;
  for (int k = 1; k <= K; ++k) t.push_back(static_cast<double>(k) / K);
  const auto minimizer = make_minimizer("ssn");
  PathSolution out;
  double seconds = 0.0;
  for (auto _ : state) {
    ContactProblem p = problem_of(mesh_of(n), kind);
    const auto t0 = std::chrono::steady_clock::now();
    out = solve_path(p, cholmod(), *minimizer, PathLoading{t, {}});
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  if (!out.converged()) state.SkipWithError("a step did not converge");
  auto& s = static_seconds()[{n, static_cast<int>(kind)}];
  if (s == 0.0) s = solve_once(n, kind);
  state.counters["solves"] = seconds / s;
  state.counters["steps"] = static_cast<double>(out.steps.size());
  if (kind == Kind::coulomb) {  // the fixed point's Tresca problems per step
    double tresca = 0.0;
    for (const auto& step : out.steps) tresca += step.fixed_point.iterations;
    state.counters["tresca_per_step"] = tresca / static_cast<double>(out.steps.size());
  }
  for (const auto& [stage, sec] : out.timings) state.counters[stage] = sec;
}

}  // namespace

int main(int argc, char** argv) {
  const std::pair<const char*, Kind> kinds[] = {
      {"", Kind::frictionless}, {"-tresca", Kind::tresca}, {"-coulomb", Kind::coulomb}};
  for (const auto& [suffix, kind] : kinds) {
    benchmark::RegisterBenchmark((std::string("solve") + suffix).c_str(), solve, kind)
        ->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
    benchmark::RegisterBenchmark((std::string("path") + suffix).c_str(), path, kind)
        ->Args({64, 100})->Args({256, 1000})->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
