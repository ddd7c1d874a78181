#include <hemivem/mumps_factorization.hpp>

#include "mumps_engine.hpp"

// One MUMPS flavour per program: the MPI backend defines the same symbol, so a program that
// links both backends fails to link with a "multiple definition" naming it.
extern "C" {
extern const char hemivem_mumps_flavour_guard[];
const char hemivem_mumps_flavour_guard[] = "sequential MUMPS (dmumps_seq)";
}

namespace hemivem {

namespace {

/// Sequential MUMPS: one process, MUMPS' own fake MPI (USE_COMM_WORLD).
struct SerialComm {
  static bool is_root() { return true; }
  static MUMPS_INT fortran_comm() { return -987654; }
  static void broadcast(void*, int) {}
};

}  // namespace

struct MumpsFactorization::Impl {
  explicit Impl(const FactorizationOptions& options) : engine(options, SerialComm{}, "mumps") {}
  MumpsEngine<SerialComm> engine;
};

MumpsFactorization::MumpsFactorization(const FactorizationOptions& options)
    : impl_(std::make_unique<Impl>(options)) {}

MumpsFactorization::~MumpsFactorization() = default;

FactorizationResult MumpsFactorization::analyze(const SparseMatrix& A) { return impl_->engine.analyze(A); }

FactorizationResult MumpsFactorization::factorize(const SparseMatrix& A) { return impl_->engine.factorize(A); }

FactorizationResult MumpsFactorization::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const {
  return impl_->engine.solve(B, X);
}

FactorizationResult MumpsFactorization::schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                                         Eigen::MatrixXd* S) {
  return impl_->engine.schur_complement(A, block1, S);
}

FactorizationResult MumpsFactorization::solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const {
  return impl_->engine.solve_interior(B2, X2);
}

double MumpsFactorization::rcond_estimate() const { return impl_->engine.rcond_estimate(); }

int MumpsFactorization::num_analyses() const noexcept { return impl_->engine.num_analyses(); }

int MumpsFactorization::num_factorizations() const noexcept { return impl_->engine.num_factorizations(); }

}  // namespace hemivem
