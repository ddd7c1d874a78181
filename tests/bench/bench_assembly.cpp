// Assembly of the global VEM stiffness: time per element on squares and Voronoi meshes.
//   build/tests/bench/bench_assembly --benchmark_counters_tabular=true
// The counter "elements/s" is the assembly rate (element matrices and the sparse matrix).
#include <benchmark/benchmark.h>

#include <hemivem/vem/assembly.hpp>
#include <hemivem/mesh/generators.hpp>

#include <map>
#include <memory>

namespace {

using namespace hemivem;

const Mesh& cached_mesh(const std::string& kind, int n) {
  static std::map<std::pair<std::string, int>, std::unique_ptr<Mesh>> cache;
  auto& slot = cache[{kind, n}];
  if (!slot) {
    if (kind == "voronoi") {
      VoronoiOptions opt;
      opt.max_lloyd_iterations = 10;  // a few Lloyd steps: cells of degree ~6 as in smoothed meshes
      slot = std::make_unique<Mesh>(make_voronoi(n, Rectangle{}, opt));
    } else {
      slot = std::make_unique<Mesh>(make_mesh(kind, n));
    }
  }
  return *slot;
}

void assemble_stiffness_bench(benchmark::State& state, const std::string& kind) {
  const Mesh& mesh = cached_mesh(kind, static_cast<int>(state.range(0)));
  const MaterialTable materials(Material{65.0, 0.29});
  for (auto _ : state) {
    SparseMatrix K = assemble_stiffness(mesh, materials);
    benchmark::DoNotOptimize(K.valuePtr());
  }
  const double ne = mesh.num_elements();
  state.counters["elements"] = ne;
  state.counters["elements/s"] = benchmark::Counter(ne, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK_CAPTURE(assemble_stiffness_bench, squares, std::string("squares"))
    ->RangeMultiplier(2)->Range(64, 512)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(assemble_stiffness_bench, voronoi, std::string("voronoi"))
    ->RangeMultiplier(2)->Range(64, 512)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
