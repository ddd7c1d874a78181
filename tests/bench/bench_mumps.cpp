// Sequential MUMPS on a plane-elasticity stiffness matrix (bilinear elements, two unknowns
// per node) of the unit square cut into N×N squares, clamped on the left and right sides:
//
//   BM_MumpsFactorize/N        analysis + factorization of the whole matrix A
//   BM_MumpsSchurBottomRow/N   schur_complement() with block1 = the y unknowns of the N−1
//                              interior nodes of the bottom row (static condensation onto a
//                              contact boundary, DESIGN §3), analysis included
//
// The ratio of the two times is the price of the condensation; MUMPS' Schur-complement feature
// should keep it near 1. Each iteration uses a fresh engine, so both include the analysis.
//   bench_mumps --benchmark_filter='/256$'
#include <hemivem/mumps_factorization.hpp>

#include <Eigen/Core>
#include <benchmark/benchmark.h>

#include <array>
#include <map>
#include <vector>

namespace {

using hemivem::SparseMatrix;

/// 8×8 plane-strain stiffness of a square bilinear element (independent of its size),
/// unknowns ordered (u_x, u_y) per corner, corners counter-clockwise from the lower left.
Eigen::Matrix<double, 8, 8> q1_element_stiffness(double E, double nu) {
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  const double mu = E / (2 * (1 + nu));
  Eigen::Matrix3d C;
  C << lambda + 2 * mu, lambda, 0, lambda, lambda + 2 * mu, 0, 0, 0, mu;
  const std::array<double, 2> xi{-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)};
  const std::array<double, 4> cx{-1, 1, 1, -1}, cy{-1, -1, 1, 1};
  Eigen::Matrix<double, 8, 8> K = Eigen::Matrix<double, 8, 8>::Zero();
  for (double s : xi)
    for (double t : xi) {
      // Reference square [-1,1]² mapped to a square of side h: dN/dx = (2/h) dN/ds and the
      // Jacobian determinant is h²/4, so h cancels; take h = 2.
      Eigen::Matrix<double, 3, 8> B = Eigen::Matrix<double, 3, 8>::Zero();
      for (int a = 0; a < 4; ++a) {
        const double dx = 0.25 * cx[a] * (1 + cy[a] * t);
        const double dy = 0.25 * cy[a] * (1 + cx[a] * s);
        B(0, 2 * a) = dx;
        B(1, 2 * a + 1) = dy;
        B(2, 2 * a) = dy;
        B(2, 2 * a + 1) = dx;
      }
      K += B.transpose() * C * B;  // weight 1, Jacobian 1
    }
  return K;
}

struct Problem {
  SparseMatrix A;
  std::vector<int> bottom_y;  // block1
};

/// Free nodes (i, j), 1 ≤ i ≤ N−1, 0 ≤ j ≤ N; node k = j (N−1) + i − 1 owns unknowns 2k, 2k+1.
Problem build(int N) {
  const auto K = q1_element_stiffness(65.0, 0.29);
  auto node = [N](int i, int j) { return (i <= 0 || i >= N) ? -1 : j * (N - 1) + (i - 1); };
  const int nodes = (N - 1) * (N + 1);
  Problem p;
  p.A.resize(2 * nodes, 2 * nodes);
  p.A.reserve(Eigen::VectorXi::Constant(2 * nodes, 18));  // 9 nodes × 2 unknowns per column
  for (int ey = 0; ey < N; ++ey)
    for (int ex = 0; ex < N; ++ex) {
      const std::array<int, 4> corner{node(ex, ey), node(ex + 1, ey), node(ex + 1, ey + 1), node(ex, ey + 1)};
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          if (corner[a] < 0 || corner[b] < 0) continue;  // clamped
          for (int c = 0; c < 2; ++c)
            for (int d = 0; d < 2; ++d)
              p.A.coeffRef(2 * corner[a] + c, 2 * corner[b] + d) += K(2 * a + c, 2 * b + d);
        }
    }
  p.A.makeCompressed();
  for (int i = 1; i < N; ++i) p.bottom_y.push_back(2 * node(i, 0) + 1);
  return p;
}

const Problem& problem(int N) {
  static std::map<int, Problem> cache;
  auto it = cache.find(N);
  if (it == cache.end()) it = cache.emplace(N, build(N)).first;
  return it->second;
}

void BM_MumpsFactorize(benchmark::State& state) {
  const Problem& p = problem(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    hemivem::MumpsFactorization mumps;
    const auto r = mumps.factorize(p.A);
    if (!r.ok()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
  }
  state.counters["unknowns"] = static_cast<double>(p.A.rows());
  state.counters["nnz"] = static_cast<double>(p.A.nonZeros());
}

void BM_MumpsSchurBottomRow(benchmark::State& state) {
  const Problem& p = problem(static_cast<int>(state.range(0)));
  Eigen::MatrixXd S;
  for (auto _ : state) {
    hemivem::MumpsFactorization mumps;
    const auto r = mumps.schur_complement(p.A, p.bottom_y, &S);
    if (!r.ok()) {
      state.SkipWithError(r.message.c_str());
      break;
    }
    benchmark::DoNotOptimize(S.data());
  }
  state.counters["unknowns"] = static_cast<double>(p.A.rows());
  state.counters["block1"] = static_cast<double>(p.bottom_y.size());
}

BENCHMARK(BM_MumpsFactorize)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MumpsSchurBottomRow)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
