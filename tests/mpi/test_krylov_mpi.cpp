// The PETSc Krylov engines on a system distributed over the processes of mpiexec
// (KrylovHints::rows, hemivem/row_distribution.hpp), reached as a full-space route reaches
// them: through hemivem::krylov alone (krylov_world(), make_distributed_rows(),
// make_krylov_solver()); the program links neither PETSc nor MPI, the factory's PETSc module
// starts MPI and finalizes it at exit.
//
// Every process runs every test. The distributed systems are the stiffness matrices of small
// spring trusses in 3D (block size 3, the six rigid motions as near-null space) which every
// process assembles whole; each keeps its rows in local columns and the gathered solution is
// compared with an independent sequential one (Eigen's SimplicialLDLT of the whole matrix).
// The rows are split unevenly (process 0 owns a single node when there are several). The
// checks never stop a process before a collective call the others make, so a failure cannot
// hang the program; main() reduces the outcome over all processes.
#include <hemivem/error.hpp>
#include <hemivem/every_process.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/row_distribution.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace {

using namespace hemivem;

const ProcessWorld& world() {
  static const ProcessWorld w = krylov_world();
  return w;
}

/// The stiffness matrix of a truss of unit springs on the (cells+1)^3 nodes of a box of
/// nx x ny x nz unit cells, every pair of a cell's 8 corners joined (a rigid truss), the nodes
/// of the face x = 0 clamped: three unknowns per free node (node-major), and the six rigid
/// motions of the free nodes as near-null space.
struct Truss {
  SparseMatrix K;
  Eigen::MatrixXd rigid;
  int nodes = 0;  // free nodes
};

Truss make_truss(int nx, int ny, int nz) {
  const auto node = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  const int all = (nx + 1) * (ny + 1) * (nz + 1);
  std::vector<int> free_index(static_cast<std::size_t>(all), -1);
  std::vector<Eigen::Vector3d> position;
  Truss t;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        if (i == 0) continue;
        free_index[static_cast<std::size_t>(node(i, j, k))] = t.nodes++;
        position.emplace_back(i, j, k);
      }
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::array<int, 8> corner{};
        std::array<Eigen::Vector3d, 8> at{};
        for (int c = 0; c < 8; ++c) {
          const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
          corner[static_cast<std::size_t>(c)] = node(i + di, j + dj, k + dk);
          at[static_cast<std::size_t>(c)] = Eigen::Vector3d(i + di, j + dj, k + dk);
        }
        for (int a = 0; a < 8; ++a)
          for (int b = a + 1; b < 8; ++b) {
            const Eigen::Vector3d d = (at[static_cast<std::size_t>(b)] - at[static_cast<std::size_t>(a)]).normalized();
            const Eigen::Matrix3d k3 = d * d.transpose();
            const int ends[2] = {free_index[static_cast<std::size_t>(corner[static_cast<std::size_t>(a)])],
                                 free_index[static_cast<std::size_t>(corner[static_cast<std::size_t>(b)])]};
            for (int p = 0; p < 2; ++p)
              for (int q = 0; q < 2; ++q) {
                if (ends[p] < 0 || ends[q] < 0) continue;
                const double sign = p == q ? 1.0 : -1.0;
                for (int r = 0; r < 3; ++r)
                  for (int s = 0; s < 3; ++s)
                    entries.emplace_back(3 * ends[p] + r, 3 * ends[q] + s, sign * k3(r, s));
              }
          }
      }
  const int n = 3 * t.nodes;
  t.K.resize(n, n);
  t.K.setFromTriplets(entries.begin(), entries.end());
  t.K.makeCompressed();
  t.rigid.setZero(n, 6);
  for (int v = 0; v < t.nodes; ++v) {
    const Eigen::Vector3d& p = position[static_cast<std::size_t>(v)];
    for (int c = 0; c < 3; ++c) t.rigid(3 * v + c, c) = 1.0;
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d w = Eigen::Vector3d::Unit(axis).cross(p);
      t.rigid.block<3, 1>(3 * v, 3 + axis) = w;
    }
  }
  return t;
}

/// The nodes each process owns: all of them in one process; otherwise one node on process 0,
/// the others split evenly, the remainder on the last process.
RowLayout node_split(int nodes, int block) {
  const int p = world().size, r = world().rank;
  std::vector<int> count(static_cast<std::size_t>(p), 0);
  if (p == 1) {
    count[0] = nodes;
  } else {
    count[0] = 1;
    const int each = (nodes - 1) / (p - 1);
    for (int q = 1; q < p; ++q) count[static_cast<std::size_t>(q)] = each;
    count.back() += nodes - 1 - each * (p - 1);
  }
  RowLayout layout;
  for (int q = 0; q < r; ++q) layout.first += block * count[static_cast<std::size_t>(q)];
  layout.owned = block * count[static_cast<std::size_t>(r)];
  layout.global = block * nodes;
  return layout;
}

/// This process's rows of the symmetric M, in local columns; `layout` gets the ghosts they read.
SparseMatrix local_rows(const SparseMatrix& M, RowLayout* layout) {
  const Eigen::Index first = layout->first, end = layout->first + layout->owned;
  std::vector<Eigen::Index> ghosts;
  for (Eigen::Index i = first; i < end; ++i)
    for (SparseMatrix::InnerIterator it(M, i); it; ++it)  // column i = row i (M symmetric)
      if (it.row() < first || it.row() >= end) ghosts.push_back(it.row());
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  layout->ghosts = ghosts;
  const auto local = [&](Eigen::Index g) {
    if (g >= first && g < end) return g - first;
    return layout->owned + (std::lower_bound(ghosts.begin(), ghosts.end(), g) - ghosts.begin());
  };
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index i = first; i < end; ++i)
    for (SparseMatrix::InnerIterator it(M, i); it; ++it) entries.emplace_back(i - first, local(it.row()), it.value());
  SparseMatrix A(layout->owned, layout->owned + static_cast<Eigen::Index>(ghosts.size()));
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  return A;
}

/// The 2-norm condition number of the SPD M (dense eigenvalues: the test's matrices are small).
double condition(const SparseMatrix& M) {
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(M)).eigenvalues();
  return lambda.maxCoeff() / lambda.minCoeff();
}

constexpr double kRtol = 1e-10;

/// The gathered solution x of K x = b against SimplicialLDLT's: the engine returns a true
/// relative residual rho <= rtol, and then ||x - x*|| / ||x*|| <= cond(K) rho (a bound, with
/// a margin for the round-off of the reference itself, cond(K) 1e-13).
void expect_solution(const SparseMatrix& K, const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                     const KrylovSolveResult& result, const std::string& what) {
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(K);
  ASSERT_EQ(ldlt.info(), Eigen::Success) << what;
  const Eigen::VectorXd reference = ldlt.solve(b);
  ASSERT_EQ(x.size(), reference.size()) << what;
  const double kappa = condition(K);
  const double residual = (b - K * x).norm() / b.norm();
  EXPECT_TRUE(result.ok()) << what << ": " << result.message;
  EXPECT_LE(result.relative_residual, kRtol) << what;
  EXPECT_NEAR(residual, result.relative_residual, 1e-2 * kRtol) << what;
  EXPECT_LE((x - reference).norm() / reference.norm(), kappa * (result.relative_residual + 1e-13))
      << what << " (condition number " << kappa << ")";
}

/// A right-hand side the same on every process.
Eigen::VectorXd load(Eigen::Index n) {
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) b(i) = std::sin(0.7 * static_cast<double>(i) + 0.3) + 0.1;
  return b;
}

/// Distributed rows of one row per process, for the checks of main() and the tests.
std::unique_ptr<RowDistribution> one_row_each() {
  RowLayout layout;
  layout.first = world().rank;
  layout.owned = 1;
  layout.global = world().size;
  return make_distributed_rows(layout);
}

TEST(KrylovMpi, WorldAndRows) {
  const auto rows = one_row_each();
  EXPECT_EQ(rows->rank(), world().rank);
  EXPECT_EQ(rows->size(), world().size);
  EXPECT_GE(world().rank, 0);
  EXPECT_LT(world().rank, world().size);
}

TEST(KrylovMpi, Collectives) {
  const int p = world().size, r = world().rank;
  // process 1 owns no row; the others r + 2
  const auto owns = [](int q) { return q == 1 ? 0 : q + 2; };
  RowLayout layout;
  for (int q = 0; q < p; ++q) {
    if (q < r) layout.first += owns(q);
    layout.global += owns(q);
  }
  layout.owned = owns(r);
  // ghosts: the first and last rows of every other process that owns some
  Eigen::Index start = 0;
  for (int q = 0; q < p; ++q) {
    if (q != r && owns(q) > 0) {
      layout.ghosts.push_back(start);
      if (owns(q) > 1) layout.ghosts.push_back(start + owns(q) - 1);
    }
    start += owns(q);
  }
  const auto rows = make_distributed_rows(layout);
  ASSERT_EQ(rows->size(), p);  // every process alike
  EXPECT_EQ(rows->layout().owned, layout.owned);
  EXPECT_EQ(rows->columns(), layout.owned + static_cast<Eigen::Index>(layout.ghosts.size()));

  EXPECT_DOUBLE_EQ(rows->sum(r + 1.0), p * (p + 1) / 2.0);
  EXPECT_DOUBLE_EQ(rows->max(static_cast<double>(r)), p - 1.0);
  EXPECT_DOUBLE_EQ(rows->min(static_cast<double>(r)), 0.0);

  // update_ghosts: entry g holds 10 g + 1 on its owner
  Eigen::VectorXd v = Eigen::VectorXd::Constant(rows->columns(), -1.0);
  for (Eigen::Index i = 0; i < layout.owned; ++i) v(i) = 10.0 * static_cast<double>(layout.first + i) + 1.0;
  const Eigen::VectorXd owned_before = v.head(layout.owned);
  rows->update_ghosts(v);
  EXPECT_EQ(v.head(layout.owned), owned_before);
  for (std::size_t i = 0; i < layout.ghosts.size(); ++i)
    EXPECT_EQ(v(layout.owned + static_cast<Eigen::Index>(i)), 10.0 * static_cast<double>(layout.ghosts[i]) + 1.0)
        << "ghost " << layout.ghosts[i];
  // a second exchange after the owners changed their values
  v.head(layout.owned).array() += 0.5;
  rows->update_ghosts(v);
  for (std::size_t i = 0; i < layout.ghosts.size(); ++i)
    EXPECT_EQ(v(layout.owned + static_cast<Eigen::Index>(i)), 10.0 * static_cast<double>(layout.ghosts[i]) + 1.5);

  // all_gather of the owned entries: the whole vector
  const Eigen::VectorXd whole = rows->all_gather(v.head(layout.owned));
  ASSERT_EQ(whole.size(), layout.global);
  for (Eigen::Index g = 0; g < layout.global; ++g) EXPECT_EQ(whole(g), 10.0 * static_cast<double>(g) + 1.5);

  // all_gather of unequal sizes: process q gives q entries 100 q + j (process 0 none)
  Eigen::VectorXd mine(r);
  for (int j = 0; j < r; ++j) mine(j) = 100.0 * r + j;
  const Eigen::VectorXd gathered = rows->all_gather(mine);
  std::vector<double> expected;
  for (int q = 0; q < p; ++q)
    for (int j = 0; j < q; ++j) expected.push_back(100.0 * q + j);
  ASSERT_EQ(gathered.size(), static_cast<Eigen::Index>(expected.size()));
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(gathered(static_cast<Eigen::Index>(i)), expected[i]);

  // a vector that does not fit on one process: InternalError on every process (in one process
  // the rows are OneProcessRows, whose update_ghosts() does nothing)
  if (p > 1) {
    Eigen::VectorXd wrong = Eigen::VectorXd::Zero(rows->columns() + (r == p - 1 ? 1 : 0));
    EXPECT_THROW(rows->update_ghosts(wrong), InternalError);
  }
}

// what the first process makes for each process, sent to it (send_to, receive_from_first,
// made_by_first): each process receives its own bytes, of any size, in the order sent; when
// the making stops on the first, the processes it has not sent to end saying so, the others
// have theirs, and none waits
TEST(KrylovMpi, WhatTheFirstMakesForEachProcessIsSentToIt) {
  const int p = world().size, r = world().rank;
  const auto rows = one_row_each();
  // process q gets 1000 q + 7 bytes, byte j = (q + j) mod 251, made in turn
  const auto bytes_for = [](int q) {
    std::vector<char> b(static_cast<std::size_t>(1000 * q + 7));
    for (std::size_t j = 0; j < b.size(); ++j) b[j] = static_cast<char>((static_cast<std::size_t>(q) + j) % 251);
    return b;
  };
  std::vector<int> made_for;
  const auto write = [](const std::vector<char>& v, std::vector<char>& out) { out.insert(out.end(), v.begin(), v.end()); };
  const auto read = [](std::span<const char> b) { return std::vector<char>(b.begin(), b.end()); };
  const std::vector<char> mine = made_by_first<std::vector<char>>(
      *rows,
      [&](const auto& deliver) {
        for (int q = p - 1; q >= 0; --q) {  // the last first: any order
          made_for.push_back(q);
          deliver(q, bytes_for(q));
        }
      },
      write, read);
  EXPECT_EQ(mine, bytes_for(r));
  if (r == 0) EXPECT_EQ(static_cast<int>(made_for.size()), p);
  else EXPECT_TRUE(made_for.empty());  // made on the first alone
  // two messages in a row to each, taken in their order
  if (p > 1) {
    if (r == 0)
      for (int q = 1; q < p; ++q) {
        rows->send_to(q, std::vector<char>{'a', static_cast<char>(q)});
        rows->send_to(q, std::vector<char>());
      }
    else {
      EXPECT_EQ(rows->receive_from_first(), (std::vector<char>{'a', static_cast<char>(r)}));
      EXPECT_TRUE(rows->receive_from_first().empty());
    }
  }
  // the making stops after the piece of process 1: process 1 has its bytes, the others end
  std::string met;
  try {
    (void)made_by_first<std::vector<char>>(
        *rows,
        [&](const auto& deliver) {
          if (p > 1) deliver(1, bytes_for(1));
          throw InputError("the third piece is not there");
        },
        write, read);
  } catch (const InputError& e) {
    met = e.what();
  }
  if (r == 0) EXPECT_EQ(met, "the third piece is not there");
  else if (r == 1) EXPECT_EQ(met, "");
  else EXPECT_EQ(met, "process 0 stopped: the third piece is not there");
  EXPECT_EQ(rows->sum(1.0), p);  // every process is here: none waits
}

// what the first gives every process at once (MPI_Bcast) reaches each whole, in place of what
// it held; an empty one too
TEST(KrylovMpi, WhatTheFirstGivesEveryProcessReachesEach) {
  const int r = world().rank;
  const auto rows = one_row_each();
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{300007}}) {
    std::vector<char> bytes(r == 0 ? n : 5, 'x');  // the others' replaced
    if (r == 0)
      for (std::size_t j = 0; j < n; ++j) bytes[j] = static_cast<char>(j % 253);
    rows->broadcast_from_first(bytes);
    ASSERT_EQ(bytes.size(), n) << "process " << r;
    std::size_t wrong = 0;
    for (std::size_t j = 0; j < n; ++j) wrong += bytes[j] == static_cast<char>(j % 253) ? 0 : 1;
    EXPECT_EQ(wrong, 0u) << "process " << r;
  }
  EXPECT_EQ(rows->sum(1.0), world().size);
}

/// The message of the InternalError make_distributed_rows(layout) throws ("" when none).
std::string refusal(const RowLayout& layout) {
  try {
    make_distributed_rows(layout);
  } catch (const InternalError& e) {
    return e.what();
  }
  return {};
}

/// True when `text` has the same length on every process.
bool same_everywhere(const std::string& text) {
  const auto rows = one_row_each();
  const double n = static_cast<double>(text.size());
  return rows->max(n) == n && rows->min(n) == n;
}

TEST(KrylovMpi, InconsistentLayoutsAreRefusedEverywhere) {
  const int p = world().size, r = world().rank;
  // overlapping ranges (in one process: rows that are not all of them)
  RowLayout overlapping;
  overlapping.first = 2 * r;
  overlapping.owned = 3;
  overlapping.global = 2 * p + 2;
  const std::string overlap = refusal(overlapping);
  EXPECT_NE(overlap.find("inconsistent row layout"), std::string::npos) << overlap;
  EXPECT_TRUE(same_everywhere(overlap)) << overlap;

  // valid ranges (two rows each), the last process's ghost one of its own rows
  RowLayout own_ghost;
  own_ghost.first = 2 * r;
  own_ghost.owned = 2;
  own_ghost.global = 2 * p;
  if (r == p - 1) own_ghost.ghosts = {own_ghost.first + 1};
  const std::string ghost = refusal(own_ghost);
  EXPECT_NE(ghost.find("inconsistent row layout"), std::string::npos) << ghost;
  EXPECT_TRUE(same_everywhere(ghost)) << ghost;

  // the same ranges without it are fine
  own_ghost.ghosts.clear();
  EXPECT_EQ(refusal(own_ghost), "");
}

/// A truss, its split and this process's rows.
struct Distributed {
  Truss truss = make_truss(5, 3, 3);
  RowLayout layout = node_split(truss.nodes, 3);
  SparseMatrix A = local_rows(truss.K, &layout);
  std::unique_ptr<RowDistribution> rows = make_distributed_rows(layout);

  KrylovHints hints() const {
    KrylovHints h(truss.rigid.middleRows(layout.first, layout.owned), 3);
    h.rows = rows.get();
    return h;
  }
  Eigen::VectorXd owned(const Eigen::VectorXd& v) const { return v.segment(layout.first, layout.owned); }
};

class DistributedEngine : public ::testing::TestWithParam<std::string> {};

TEST_P(DistributedEngine, SolvesTheTrussAsLdlt) {
  const Distributed d;
  const Eigen::VectorXd b = load(d.truss.K.rows());
  const auto solver = make_krylov_solver(GetParam());
  const FactorizationResult computed = solver->compute(d.A, d.hints());
  ASSERT_TRUE(computed.ok()) << computed.message;  // the same on every process
  Eigen::VectorXd x;
  const KrylovSolveResult result = solver->solve(d.owned(b), &x, kRtol, 500);
  ASSERT_EQ(x.size(), d.layout.owned);
  const Eigen::VectorXd whole = d.rows->all_gather(x);
  expect_solution(d.truss.K, b, whole, result, GetParam());
  EXPECT_GT(result.iterations, 0);
}

TEST_P(DistributedEngine, RowsNotCompressedAreCopiedAndSolved) {
  // the owned rows in Eigen's uncompressed storage (room left after each column): the engine
  // copies the diagonal block instead of reading it in place; a second compute() on new values
  // takes the new values
  Distributed d;
  d.A.uncompress();
  d.A.reserve(Eigen::VectorXi::Constant(d.A.outerSize(), 2));
  ASSERT_FALSE(d.A.isCompressed());
  const Eigen::VectorXd b = load(d.truss.K.rows());
  const auto solver = make_krylov_solver(GetParam());
  const KrylovHints hints = d.hints();
  const FactorizationResult computed = solver->compute(d.A, hints);
  ASSERT_TRUE(computed.ok()) << computed.message;
  Eigen::VectorXd x;
  KrylovSolveResult result = solver->solve(d.owned(b), &x, kRtol, 500);
  expect_solution(d.truss.K, b, d.rows->all_gather(x), result, GetParam() + ", uncompressed");

  for (Eigen::Index j = 0; j < d.A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(d.A, j); it; ++it) it.valueRef() *= 2.0;
  const FactorizationResult again = solver->compute(d.A, hints);
  ASSERT_TRUE(again.ok()) << again.message;
  x.setZero();
  result = solver->solve(d.owned(b), &x, kRtol, 500);
  const SparseMatrix K2 = 2.0 * d.truss.K;
  expect_solution(K2, b, d.rows->all_gather(x), result, GetParam() + ", uncompressed, doubled");
}

TEST_P(DistributedEngine, ValuesChangedInPlaceAreTheNewSystem) {
  Distributed d;
  const Eigen::VectorXd b = load(d.truss.K.rows());
  const auto solver = make_krylov_solver(GetParam());
  const KrylovHints hints = d.hints();
  ASSERT_TRUE(solver->compute(d.A, hints).ok());
  Eigen::VectorXd x;
  KrylovSolveResult result = solver->solve(d.owned(b), &x, kRtol, 500);
  expect_solution(d.truss.K, b, d.rows->all_gather(x), result, GetParam() + ", first system");

  // K2 = 0.9 (K - D) + 1.5 D, D the diagonal of K: every value of the owned rows changed in
  // place (local column i of owned row i, the diagonal; the others, those of the ghost columns
  // in the off-diagonal block among them, by 0.9), the pattern not
  const double* values_before = d.A.valuePtr();
  Eigen::Index ghost_entries = 0;
  for (Eigen::Index j = 0; j < d.A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(d.A, j); it; ++it) {
      it.valueRef() *= it.row() == j ? 1.5 : 0.9;
      ghost_entries += j >= d.layout.owned ? 1 : 0;
    }
  ASSERT_EQ(d.A.valuePtr(), values_before);
  if (d.rows->size() > 1) EXPECT_GT(d.rows->sum(static_cast<double>(ghost_entries)), 0.0);
  SparseMatrix K2 = d.truss.K;
  for (Eigen::Index j = 0; j < K2.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(K2, j); it; ++it) it.valueRef() *= it.row() == j ? 1.5 : 0.9;
  const FactorizationResult again = solver->compute(d.A, hints);
  ASSERT_TRUE(again.ok()) << again.message;
  x.setZero();
  result = solver->solve(d.owned(b), &x, kRtol, 500);
  expect_solution(K2, b, d.rows->all_gather(x), result, GetParam() + ", values changed in place");
}

TEST_P(DistributedEngine, ArgumentsThatDoNotFitOneProcessThrowEverywhere) {
  const Distributed d;
  const auto solver = make_krylov_solver(GetParam());
  KrylovHints hints = d.hints();
  // the last process's near-null space lacks a row
  Eigen::MatrixXd shorter = hints.near_null;
  if (world().rank == world().size - 1 && world().size > 1) shorter.conservativeResize(shorter.rows() - 1, Eigen::NoChange);
  if (world().size > 1) {
    hints.near_null = shorter;
    EXPECT_THROW(solver->compute(d.A, hints), InternalError);
    hints = d.hints();
  }
  ASSERT_TRUE(solver->compute(d.A, hints).ok());
  // the last process's right-hand side lacks a row
  Eigen::VectorXd b = d.owned(load(d.truss.K.rows()));
  if (world().rank == world().size - 1) b.conservativeResize(b.size() - 1);
  Eigen::VectorXd x;
  EXPECT_THROW(solver->solve(b, &x, kRtol, 500), InternalError);
  // b = 0 everywhere: x = 0 at once
  b = Eigen::VectorXd::Zero(d.layout.owned);
  x = Eigen::VectorXd::Ones(d.layout.owned);
  const KrylovSolveResult zero = solver->solve(b, &x, kRtol, 500);
  EXPECT_TRUE(zero.ok()) << zero.message;
  EXPECT_EQ(zero.iterations, 0);
  EXPECT_EQ(x, Eigen::VectorXd::Zero(d.layout.owned));
}

TEST_P(DistributedEngine, ANegativeDiagonalOnOneProcessIsNotPositiveDefiniteEverywhere) {
  Distributed d;
  const auto solver = make_krylov_solver(GetParam());
  if (world().rank == world().size - 1) d.A.coeffRef(0, 0) = -1.0;
  const FactorizationResult computed = solver->compute(d.A, d.hints());
  EXPECT_EQ(computed.status, FactorizationStatus::not_positive_definite) << computed.message;
  const Eigen::Index row = d.layout.first;  // the last process's first row, on the last process
  if (world().rank == world().size - 1) {
    EXPECT_NE(computed.message.find("diagonal entry " + std::to_string(row)), std::string::npos) << computed.message;
  }
  EXPECT_TRUE(same_everywhere(computed.message)) << computed.message;
}

INSTANTIATE_TEST_SUITE_P(Petsc, DistributedEngine, ::testing::Values("petsc-gamg", "petsc-hypre"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

/// Every engine with the whole matrix in each process (OneProcessRows): the sequential path,
/// under mpiexec too.
TEST(KrylovMpi, OneProcessRowsSolveTheWholeSystemInEachProcess) {
  const Truss truss = make_truss(4, 2, 2);
  const Eigen::VectorXd b = load(truss.K.rows());
  const OneProcessRows rows(truss.K.rows());
  for (const std::string& engine : available_krylov_solvers()) {
    const auto solver = make_krylov_solver(engine);
    KrylovHints hints(truss.rigid, 3);
    hints.rows = &rows;
    const FactorizationResult computed = solver->compute(truss.K, hints);
    ASSERT_TRUE(computed.ok()) << engine << ": " << computed.message;
    Eigen::VectorXd x;
    const KrylovSolveResult result = solver->solve(b, &x, kRtol, 2000);
    expect_solution(truss.K, b, x, result, engine + " in one process");
  }
}

TEST(KrylovMpi, EigenCgRefusesSeveralProcesses) {
  const Distributed d;
  const auto solver = make_krylov_solver("eigen-cg");
  if (world().size == 1) {
    // in one process the rows are OneProcessRows: eigen-cg solves
    ASSERT_TRUE(solver->compute(d.A, d.hints()).ok());
    Eigen::VectorXd x;
    const Eigen::VectorXd b = load(d.truss.K.rows());
    expect_solution(d.truss.K, b, x, solver->solve(b, &x, kRtol, 2000), "eigen-cg, rows of one process");
    return;
  }
  try {
    solver->compute(d.A, d.hints());
    ADD_FAILURE() << "eigen-cg accepted rows of " << world().size << " processes";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("eigen-cg runs in one process"), std::string::npos) << e.what();
  }
}

/// Prints the failures of a process other than 0, prefixed with its rank.
class RankFailurePrinter : public ::testing::EmptyTestEventListener {
 public:
  explicit RankFailurePrinter(int rank) : rank_(rank) {}
  void OnTestPartResult(const ::testing::TestPartResult& result) override {
    if (result.failed())
      std::fprintf(stderr, "[rank %d] %s:%d: failure\n%s\n", rank_, result.file_name() ? result.file_name() : "?",
                   result.line_number(), result.summary());
  }

 private:
  int rank_;
};

}  // namespace

// As tests/mpi/mpi_test_main.hpp, through hemivem::krylov instead of MPI: rank 0 prints
// GoogleTest's report, the others their failures; the program fails on every process when a
// test failed on any. PETSc (and MPI with it) is finalized at exit by the PETSc module.
int main(int argc, char** argv) {
  const ProcessWorld& w = world();
  ::testing::InitGoogleTest(&argc, argv);
  if (w.rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new RankFailurePrinter(w.rank));
  } else {
    std::printf("distributed Krylov tests on %d process%s\n", w.size, w.size > 1 ? "es" : "");
  }
  const double failed_here = RUN_ALL_TESTS() != 0 ? 1.0 : 0.0;
  const double failed_anywhere = one_row_each()->max(failed_here);
  if (w.rank == 0 && failed_anywhere > 0.0 && failed_here == 0.0)
    std::printf("FAILED on a process other than rank 0 (see its output above)\n");
  return failed_anywhere > 0.0 ? 1 : 0;
}
