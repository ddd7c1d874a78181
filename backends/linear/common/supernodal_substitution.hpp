// Forward and backward substitution with the leading columns of a supernodal Cholesky factor
// for a few right-hand sides at once (private to backends/linear). A substitution with one or
// a few columns is bound by reading the factor from memory: these loops read each supernode's
// block once for all M columns, where a dense matrix-matrix product would first copy (pack) the
// block, and a product per column would read it M times.
#pragma once

#include <algorithm>
#include <vector>

namespace hemivem::linear_detail {

/// One supernode's part of a substitution: its first column j0, its nc columns of the leading
/// block (nc <= ncol), the count rows below them that are read (rows[nc] .. rows[nc + count - 1]),
/// and its column-major block of ld rows.
struct SupernodePiece {
  int j0 = 0, nc = 0, count = 0, ld = 0;
  const int* rows = nullptr;
  const double* values = nullptr;
};

/// Z (rows x M, row-major: row r at z + r * M) = L^{-1} Z with the pieces in order; each
/// piece solves with its diagonal block and subtracts its block below from the rows it names.
template <int M, class Pieces>
void forward_few(const Pieces& pieces, double* z, std::vector<double>& acc) {
  for (const SupernodePiece& p : pieces) {
    const double* B = p.values;
    for (int j = 0; j < p.nc; ++j) {  // the diagonal block, column by column
      const double* col = B + static_cast<std::ptrdiff_t>(j) * p.ld;
      double* zj = z + static_cast<std::ptrdiff_t>(p.j0 + j) * M;
      for (int c = 0; c < M; ++c) zj[c] /= col[j];
      for (int i = j + 1; i < p.nc; ++i) {
        double* zi = z + static_cast<std::ptrdiff_t>(p.j0 + i) * M;
        for (int c = 0; c < M; ++c) zi[c] -= col[i] * zj[c];
      }
    }
    if (p.count == 0) continue;
    acc.assign(static_cast<std::size_t>(p.count) * M, 0.0);
    double* a = acc.data();
    // four columns at a time, so that each entry of acc is loaded and stored once per four
    int j = 0;
    for (; j + 4 <= p.nc; j += 4) {
      const double* col = B + static_cast<std::ptrdiff_t>(j) * p.ld + p.nc;
      const double* zj = z + static_cast<std::ptrdiff_t>(p.j0 + j) * M;
      for (int r = 0; r < p.count; ++r)
        for (int c = 0; c < M; ++c)
          a[r * M + c] += (col[r] * zj[c] + col[r + p.ld] * zj[M + c]) +
                          (col[r + 2 * p.ld] * zj[2 * M + c] + col[r + 3 * p.ld] * zj[3 * M + c]);
    }
    for (; j < p.nc; ++j) {
      const double* col = B + static_cast<std::ptrdiff_t>(j) * p.ld + p.nc;
      const double* zj = z + static_cast<std::ptrdiff_t>(p.j0 + j) * M;
      for (int r = 0; r < p.count; ++r)
        for (int c = 0; c < M; ++c) a[r * M + c] += col[r] * zj[c];
    }
    for (int r = 0; r < p.count; ++r) {
      double* zr = z + static_cast<std::ptrdiff_t>(p.rows[p.nc + r]) * M;
      for (int c = 0; c < M; ++c) zr[c] -= a[r * M + c];
    }
  }
}

/// Z = L^{-T} Z with the same pieces, taken in reverse order. Every loop runs downwards, so
/// that the whole pass reads the factor from its end to its start as one descending stream,
/// which the processor's prefetcher follows as it does an ascending one.
template <int M, class Pieces>
void backward_few(const Pieces& pieces, double* z, std::vector<double>& gathered) {
  for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) {
    const SupernodePiece& p = *it;
    const double* B = p.values;
    if (p.count > 0) {
      gathered.resize(static_cast<std::size_t>(p.count) * M);
      double* g = gathered.data();
      for (int r = 0; r < p.count; ++r)
        std::copy_n(z + static_cast<std::ptrdiff_t>(p.rows[p.nc + r]) * M, M, g + static_cast<std::ptrdiff_t>(r) * M);
      for (int j = p.nc - 1; j >= 0; --j) {
        const double* col = B + static_cast<std::ptrdiff_t>(j) * p.ld + p.nc;
        // four partial sums per column, so that the dot products do not wait on one another
        double s[4][M] = {};
        int r = p.count;
        for (; r >= 4; r -= 4)
          for (int q = 1; q <= 4; ++q)
            for (int c = 0; c < M; ++c) s[q - 1][c] += col[r - q] * g[(r - q) * M + c];
        for (; r > 0; --r)
          for (int c = 0; c < M; ++c) s[0][c] += col[r - 1] * g[(r - 1) * M + c];
        double* zj = z + static_cast<std::ptrdiff_t>(p.j0 + j) * M;
        for (int c = 0; c < M; ++c) zj[c] -= (s[0][c] + s[1][c]) + (s[2][c] + s[3][c]);
      }
    }
    for (int j = p.nc - 1; j >= 0; --j) {  // the diagonal block, transposed, from its last column
      const double* col = B + static_cast<std::ptrdiff_t>(j) * p.ld;
      double* zj = z + static_cast<std::ptrdiff_t>(p.j0 + j) * M;
      for (int i = p.nc - 1; i > j; --i) {
        const double* zi = z + static_cast<std::ptrdiff_t>(p.j0 + i) * M;
        for (int c = 0; c < M; ++c) zj[c] -= col[i] * zi[c];
      }
      for (int c = 0; c < M; ++c) zj[c] /= col[j];
    }
  }
}

}  // namespace hemivem::linear_detail
