// Forward and backward substitution with the leading columns of a supernodal Cholesky factor
// for a few right-hand sides at once (private to backends/linear). A substitution with one or
// a few columns reads the whole factor for little arithmetic:
//   - each supernode's block is read once for all M columns, where a dense matrix-matrix
//     product would first copy (pack) the block, and a product per column would read it M times;
//   - the block is read column by column, each column from its diagonal down (backward: up), so
//     that a pass reads the factor as one stream, which the processor's prefetcher follows;
//   - where the factor is large, the supernodes are split into two sets of independent subtrees
//     of about equal work and what lies above them (SubstitutionSchedule): the two sets are
//     substituted on two threads at once, the rest on one. The split depends on the factor's
//     structure alone, so the result is the same bit for bit on one thread or two.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <functional>
#include <system_error>
#include <thread>
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

/// y (n rows of M values) -= (or +=) the column c (n values) times w (M values).
template <int M, bool subtract>
inline void axpy_rows(const double* __restrict__ c, const double* __restrict__ w, double* __restrict__ y, int n) {
  for (int i = 0; i < n; ++i)
    for (int m = 0; m < M; ++m) {
      if constexpr (subtract)
        y[i * M + m] -= c[i] * w[m];
      else
        y[i * M + m] += c[i] * w[m];
    }
}

/// s (M values) += the column c (n values) transposed times y (n rows of M values), from the
/// last row up, in P interleaved partial sums so that the products do not wait on each other.
template <int M>
inline void dot_rows(const double* __restrict__ c, const double* __restrict__ y, int n, double* __restrict__ s) {
  constexpr int P = M == 1 ? 4 : 2;
  double part[P][M] = {};
  int i = n;
  for (; i >= P; i -= P)
    for (int q = 0; q < P; ++q)
      for (int m = 0; m < M; ++m) part[q][m] += c[i - 1 - q] * y[(i - 1 - q) * M + m];
  for (; i > 0; --i)
    for (int m = 0; m < M; ++m) part[0][m] += c[i - 1] * y[(i - 1) * M + m];
  for (int m = 0; m < M; ++m) {
    double t = part[0][m];
    for (int q = 1; q < P; ++q) t += part[q][m];
    s[m] += t;
  }
}

/// Z (rows x M, row-major: row r at z + r * M) = L^{-1} Z on one piece: solves with its
/// diagonal block, sums its rows below the block times the solved rows into acc and calls
/// scatter(p, acc), which subtracts acc's rows from the rows of Z that the piece names.
template <int M, class Scatter>
inline void forward_piece(const SupernodePiece& p, double* z, std::vector<double>& acc, Scatter&& scatter) {
  double* zs = z + static_cast<std::ptrdiff_t>(p.j0) * M;
  acc.assign(static_cast<std::size_t>(p.count) * M, 0.0);
  for (int j = 0; j < p.nc; ++j) {
    const double* col = p.values + static_cast<std::ptrdiff_t>(j) * p.ld;
    double* zj = zs + static_cast<std::ptrdiff_t>(j) * M;
    double w[M];
    for (int m = 0; m < M; ++m) w[m] = zj[m] /= col[j];
    axpy_rows<M, true>(col + j + 1, w, zj + M, p.nc - j - 1);
    axpy_rows<M, false>(col + p.nc, w, acc.data(), p.count);
  }
  if (p.count > 0) scatter(p, acc.data());
}

/// Z = L^{-T} Z on one piece: the rows of Z below its block (those it names, final already)
/// and its own rows are read, its own rows written.
template <int M>
inline void backward_piece(const SupernodePiece& p, double* z, std::vector<double>& gathered) {
  double* zs = z + static_cast<std::ptrdiff_t>(p.j0) * M;
  gathered.resize(static_cast<std::size_t>(p.count) * M);
  double* g = gathered.data();
  for (int r = 0; r < p.count; ++r)
    std::copy_n(z + static_cast<std::ptrdiff_t>(p.rows[p.nc + r]) * M, M, g + static_cast<std::ptrdiff_t>(r) * M);
  for (int j = p.nc - 1; j >= 0; --j) {
    const double* col = p.values + static_cast<std::ptrdiff_t>(j) * p.ld;
    double s[M] = {};
    dot_rows<M>(col + p.nc, g, p.count, s);
    dot_rows<M>(col + j + 1, zs + static_cast<std::ptrdiff_t>(j + 1) * M, p.nc - j - 1, s);
    for (int m = 0; m < M; ++m) zs[static_cast<std::ptrdiff_t>(j) * M + m] = (zs[static_cast<std::ptrdiff_t>(j) * M + m] - s[m]) / col[j];
  }
}

/// How a substitution is shared between two threads. The pieces (supernodes in postorder) fall
/// into the subtrees given to each thread, contiguous ranges of pieces and of columns, and the
/// top: the pieces above them, substituted on one thread (forward: after both sets; backward:
/// before). Forward, a subtree's updates of rows outside its columns (the top's columns, the
/// rows at or after n2) are summed per thread in slots and subtracted after both are done, in
/// the order of the threads.
struct SubstitutionSchedule {
  struct Range {
    int begin = 0, end = 0;  // pieces
    int column_end = 0;      // the first column after the subtree's
  };
  bool split = false;               // false: every piece in order on one thread
  std::vector<Range> ranges[2];     // each thread's subtrees, in increasing order
  std::vector<int> top;             // the other pieces, increasing
  std::vector<int> slot;            // row -> its slot (rows outside every subtree), else -1
  std::vector<int> slot_row;        // slot -> row
};

/// The supernodes' elimination tree (within L22): each piece's parent (-1: a root), the work
/// of its subtree (entries read), its size in pieces and its children. Empty where the pieces are
/// not in postorder (a parent before its child).
struct SupernodeTree {
  std::vector<double> work, sub;
  std::vector<int> size, roots;
  std::vector<std::vector<int>> children;
  double total = 0.0;
};

template <class Pieces>
bool supernode_tree(const Pieces& pieces, int n2, SupernodeTree* tree) {
  const auto np = pieces.size();
  SupernodeTree& t = *tree;
  t.work.assign(np, 0.0);
  t.size.assign(np, 1);
  t.children.assign(np, {});
  std::vector<int> parent(np, -1);
  for (std::size_t k = 0; k < np; ++k) {
    const SupernodePiece& p = pieces[k];
    t.work[k] = 0.5 * p.nc * (p.nc + 1.0) + static_cast<double>(p.nc) * p.count;
    t.total += t.work[k];
    if (p.count > 0 && p.rows[p.nc] < n2) {
      // the piece that holds the first row below the block (pieces are ordered by j0)
      const auto it = std::upper_bound(pieces.begin(), pieces.end(), p.rows[p.nc],
                                       [](int row, const SupernodePiece& q) { return row < q.j0; });
      const auto q = static_cast<std::size_t>(it - pieces.begin()) - 1;
      if (q <= k) return false;
      parent[k] = static_cast<int>(q);
    }
  }
  t.sub = t.work;
  for (std::size_t k = 0; k < np; ++k) {
    if (parent[k] < 0) {
      t.roots.push_back(static_cast<int>(k));
      continue;
    }
    const auto q = static_cast<std::size_t>(parent[k]);
    t.sub[q] += t.sub[k];
    t.size[q] += t.size[k];
    t.children[q].push_back(static_cast<int>(k));
  }
  return true;
}

/// Splits the largest subtree (its root into `top`) until the subtrees fall into two sets of
/// about equal work (largest first, each into the lighter set): the subtrees in `trees`, their
/// sets in `side`. False when no such split leaves the top under a quarter of the work.
inline bool split_subtrees(const SupernodeTree& t, std::vector<int>* trees, std::vector<int>* side, std::vector<int>* top) {
  *trees = t.roots;
  double top_work = 0.0;
  auto heavier = [&](int a, int b) {
    const double wa = t.sub[static_cast<std::size_t>(a)], wb = t.sub[static_cast<std::size_t>(b)];
    return wa > wb || (wa == wb && a < b);
  };
  for (int round = 0;; ++round) {
    std::sort(trees->begin(), trees->end(), heavier);
    double bins[2] = {0.0, 0.0};
    side->assign(trees->size(), 0);
    for (std::size_t i = 0; i < trees->size(); ++i) {
      (*side)[i] = bins[1] < bins[0] ? 1 : 0;
      bins[(*side)[i]] += t.sub[static_cast<std::size_t>((*trees)[i])];
    }
    if (trees->size() >= 2 && std::max(bins[0], bins[1]) <= 0.525 * (bins[0] + bins[1])) return true;
    if (round == 256 || trees->empty() || top_work > 0.25 * t.total) return false;
    const int root = trees->front();
    trees->erase(trees->begin());
    top->push_back(root);
    top_work += t.work[static_cast<std::size_t>(root)];
    for (int c : t.children[static_cast<std::size_t>(root)]) trees->push_back(c);
  }
}

/// The schedule of pieces (in postorder, the first n2 columns; rows below read up to `end`): a
/// split into two sets of subtrees when the pieces hold at least min_entries entries and a split
/// with sets within 5 % of each other is found with a small top, else none.
template <class Pieces>
SubstitutionSchedule schedule_substitution(const Pieces& pieces, int n2, int end, double min_entries) {
  SubstitutionSchedule s;
  SupernodeTree tree;
  if (pieces.size() < 2 || !supernode_tree(pieces, n2, &tree) || tree.total < min_entries) return s;
  std::vector<int> trees, side, top;
  if (!split_subtrees(tree, &trees, &side, &top)) return s;
  s.split = true;
  for (std::size_t i = 0; i < trees.size(); ++i) {
    const int k = trees[i];
    const SupernodePiece& p = pieces[static_cast<std::size_t>(k)];
    s.ranges[side[i]].push_back({k - tree.size[static_cast<std::size_t>(k)] + 1, k + 1, p.j0 + p.nc});
  }
  for (auto& r : s.ranges)
    std::sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.begin < b.begin; });
  std::sort(top.begin(), top.end());
  s.top = std::move(top);
  // the slots: the top's columns, then the rows at or after n2
  s.slot.assign(static_cast<std::size_t>(end), -1);
  auto add_slot = [&](int row) {
    s.slot[static_cast<std::size_t>(row)] = static_cast<int>(s.slot_row.size());
    s.slot_row.push_back(row);
  };
  for (int k : s.top)
    for (int j = pieces[static_cast<std::size_t>(k)].j0; j < pieces[static_cast<std::size_t>(k)].j0 + pieces[static_cast<std::size_t>(k)].nc; ++j) add_slot(j);
  for (int r = n2; r < end; ++r) add_slot(r);
  return s;
}

/// Runs first() on this thread and second() on another at once (on this one after first()
/// where no thread can be started); an exception of either is rethrown after both.
inline void run_both(const std::function<void()>& first, const std::function<void()>& second) {
  std::exception_ptr failure2;
  auto guarded2 = [&] {
    try {
      second();
    } catch (...) {
      failure2 = std::current_exception();
    }
  };
  std::thread worker;
  try {
    worker = std::thread(guarded2);
  } catch (const std::system_error&) {
  }
  std::exception_ptr failure1;
  try {
    first();
  } catch (...) {
    failure1 = std::current_exception();
  }
  if (worker.joinable())
    worker.join();
  else
    guarded2();
  if (failure1) std::rethrow_exception(failure1);
  if (failure2) std::rethrow_exception(failure2);
}

/// Subtracts acc's rows from the rows of Z that the piece names.
template <int M>
inline void scatter_into(const SupernodePiece& p, const double* acc, double* z) {
  for (int r = 0; r < p.count; ++r) {
    double* zr = z + static_cast<std::ptrdiff_t>(p.rows[p.nc + r]) * M;
    for (int m = 0; m < M; ++m) zr[m] -= acc[r * M + m];
  }
}

/// Z = L^{-1} Z with the pieces in order (or as the schedule shares them).
template <int M, class Pieces>
void forward_few(const Pieces& pieces, const SubstitutionSchedule& schedule, double* z) {
  std::vector<double> acc;
  auto direct = [z](const SupernodePiece& p, const double* a) { scatter_into<M>(p, a, z); };
  if (!schedule.split) {
    for (const SupernodePiece& p : pieces) forward_piece<M>(p, z, acc, direct);
    return;
  }
  std::vector<double> outside[2];
  auto set = [&](int t) {
    std::vector<double> a;
    std::vector<double>& out = outside[t];
    out.assign(schedule.slot_row.size() * M, 0.0);
    for (const auto& range : schedule.ranges[t]) {
      auto split = [&](const SupernodePiece& p, const double* acc_rows) {
        for (int r = 0; r < p.count; ++r) {
          const int row = p.rows[p.nc + r];
          double* to = row < range.column_end ? z + static_cast<std::ptrdiff_t>(row) * M
                                              : out.data() + static_cast<std::ptrdiff_t>(schedule.slot[static_cast<std::size_t>(row)]) * M;
          for (int m = 0; m < M; ++m) to[m] -= acc_rows[r * M + m];
        }
      };
      for (int k = range.begin; k < range.end; ++k) forward_piece<M>(pieces[static_cast<std::size_t>(k)], z, a, split);
    }
  };
  run_both([&] { set(0); }, [&] { set(1); });
  for (const auto& out : outside)
    for (std::size_t q = 0; q < schedule.slot_row.size(); ++q)
      for (int m = 0; m < M; ++m) z[static_cast<std::ptrdiff_t>(schedule.slot_row[q]) * M + m] += out[q * M + m];
  for (int k : schedule.top) forward_piece<M>(pieces[static_cast<std::size_t>(k)], z, acc, direct);
}

/// Z = L^{-T} Z with the pieces in reverse order (or as the schedule shares them): the whole
/// pass reads the factor from its end to its start.
template <int M, class Pieces>
void backward_few(const Pieces& pieces, const SubstitutionSchedule& schedule, double* z) {
  std::vector<double> gathered;
  if (!schedule.split) {
    for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) backward_piece<M>(*it, z, gathered);
    return;
  }
  for (auto it = schedule.top.rbegin(); it != schedule.top.rend(); ++it)
    backward_piece<M>(pieces[static_cast<std::size_t>(*it)], z, gathered);
  auto set = [&](int t) {
    std::vector<double> g;
    const auto& ranges = schedule.ranges[t];
    for (auto r = ranges.rbegin(); r != ranges.rend(); ++r)
      for (int k = r->end - 1; k >= r->begin; --k) backward_piece<M>(pieces[static_cast<std::size_t>(k)], z, g);
  };
  run_both([&] { set(0); }, [&] { set(1); });
}

}  // namespace hemivem::linear_detail
