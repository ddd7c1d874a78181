// Linear engines on a plane-elasticity-like matrix: bilinear (Q1) plane-strain elements on
// an N x N grid of unit cells, 2 dofs per node (9-point stencil per component), plus a
// small diagonal shift so the matrix is SPD without boundary conditions.
//
//   factorize/<engine>/N : analyze + factorize of the whole matrix (a fresh engine each time)
//   schur/<engine>/N     : schur_complement with block1 = the y-dofs of the N-1 interior nodes
//                          of the bottom row (a fresh engine each time)
//
// The ratio schur / factorize is what DESIGN §3 asks to be about 1.
#include <hemivem/linear_backends.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using hemivem::SparseMatrix;

struct Problem {
  SparseMatrix A;
  std::vector<int> block1;
};

/// 8x8 stiffness of a unit square Q1 element, plane strain, E = 1, nu = 0.3, 2x2 Gauss.
Eigen::Matrix<double, 8, 8> q1_stiffness() {
  const double E = 1.0, nu = 0.3;
  const double c = E / ((1 + nu) * (1 - 2 * nu));
  Eigen::Matrix3d D;
  D << c * (1 - nu), c * nu, 0, c * nu, c * (1 - nu), 0, 0, 0, c * (1 - 2 * nu) / 2;
  const std::array<double, 4> xi = {-1, 1, 1, -1}, eta = {-1, -1, 1, 1};  // corner nodes
  const double g = 1.0 / std::sqrt(3.0);
  Eigen::Matrix<double, 8, 8> K = Eigen::Matrix<double, 8, 8>::Zero();
  for (double gx : {-g, g}) {
    for (double gy : {-g, g}) {
      Eigen::Matrix<double, 3, 8> B = Eigen::Matrix<double, 3, 8>::Zero();
      for (int a = 0; a < 4; ++a) {
        // unit cell: x = (1 + xi) / 2, so d/dx = 2 d/dxi
        const double dx = 2 * 0.25 * xi[a] * (1 + eta[a] * gy);
        const double dy = 2 * 0.25 * eta[a] * (1 + xi[a] * gx);
        B(0, 2 * a) = dx;
        B(1, 2 * a + 1) = dy;
        B(2, 2 * a) = dy;
        B(2, 2 * a + 1) = dx;
      }
      K += B.transpose() * D * B * 0.25;  // Jacobian determinant of the unit cell
    }
  }
  return K;
}

const Problem& problem(int N) {
  static std::map<int, Problem> cache;
  auto found = cache.find(N);
  if (found != cache.end()) return found->second;
  const auto K = q1_stiffness();
  const int nodes = (N + 1) * (N + 1);
  auto node = [N](int ix, int iy) { return iy * (N + 1) + ix; };
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(static_cast<std::size_t>(N) * N * 64 + 2 * nodes);
  for (int iy = 0; iy < N; ++iy) {
    for (int ix = 0; ix < N; ++ix) {
      const std::array<int, 4> v = {node(ix, iy), node(ix + 1, iy), node(ix + 1, iy + 1), node(ix, iy + 1)};
      for (int a = 0; a < 4; ++a)
        for (int ca = 0; ca < 2; ++ca)
          for (int b = 0; b < 4; ++b)
            for (int cb = 0; cb < 2; ++cb)
              entries.emplace_back(2 * v[a] + ca, 2 * v[b] + cb, K(2 * a + ca, 2 * b + cb));
    }
  }
  for (int i = 0; i < 2 * nodes; ++i) entries.emplace_back(i, i, 1e-6);
  Problem p;
  p.A.resize(2 * nodes, 2 * nodes);
  p.A.setFromTriplets(entries.begin(), entries.end());
  p.A.makeCompressed();
  for (int ix = 1; ix < N; ++ix) p.block1.push_back(2 * node(ix, 0) + 1);
  return cache.emplace(N, std::move(p)).first->second;
}

std::unique_ptr<hemivem::SparseFactorization> engine(const std::string& name) {
  hemivem::FactorizationOptions options;
  options.engine = name;
  return hemivem::make_factorization(options);
}

void set_counters(benchmark::State& state, const Problem& p) {
  state.counters["n"] = static_cast<double>(p.A.rows());
  state.counters["nnz"] = static_cast<double>(p.A.nonZeros());
  state.counters["n1"] = static_cast<double>(p.block1.size());
}

void factorize(benchmark::State& state, const std::string& name) {
  const Problem& p = problem(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    auto f = engine(name);
    const auto r = f->factorize(p.A);
    if (!r.ok()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
    benchmark::DoNotOptimize(f.get());
  }
  set_counters(state, p);
}

void schur(benchmark::State& state, const std::string& name) {
  const Problem& p = problem(static_cast<int>(state.range(0)));
  Eigen::MatrixXd S;
  for (auto _ : state) {
    auto f = engine(name);
    const auto r = f->schur_complement(p.A, p.block1, &S);
    if (!r.ok()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
    benchmark::DoNotOptimize(S.data());
  }
  set_counters(state, p);
}

const bool registered = [] {
  for (const std::string& name : hemivem::available_factorizations()) {
    for (auto [label, function] : {std::pair{"factorize", &factorize}, std::pair{"schur", &schur}}) {
      benchmark::RegisterBenchmark((std::string(label) + "/" + name).c_str(), function, name)
          ->Arg(64)
          ->Arg(128)
          ->Arg(256)
          ->Arg(512)
          ->Unit(benchmark::kMillisecond);
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
