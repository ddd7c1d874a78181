#include <hemivem/error.hpp>
#include <hemivem/mumps_mpi_factorization.hpp>

#include <mpi.h>

#include "mumps_engine.hpp"

// One MUMPS flavour per program: the sequential backend defines the same symbol, so a program
// that links both backends fails to link with a "multiple definition" naming it.
extern "C" {
extern const char hemivem_mumps_flavour_guard[];
const char hemivem_mumps_flavour_guard[] = "MPI MUMPS (dmumps)";
}

namespace hemivem {

namespace {

/// MPI initialized by hemivem is finalized by hemivem, at exit.
class MpiSession {
 public:
  MpiSession() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
      owned_ = true;
    }
  }
  ~MpiSession() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (owned_ && !finalized) MPI_Finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

 private:
  bool owned_ = false;
};

/// True when MPI can be used (initialized here if needed, not finalized).
bool ensure_mpi() {
  static MpiSession session;
  int finalized = 0;
  MPI_Finalized(&finalized);
  return !finalized;
}

/// MPI_COMM_WORLD, with rank 0 as MUMPS' host.
class WorldComm {
 public:
  WorldComm() { MPI_Comm_rank(MPI_COMM_WORLD, &rank_); }
  bool is_root() const { return rank_ == 0; }
  static MUMPS_INT fortran_comm() { return static_cast<MUMPS_INT>(MPI_Comm_c2f(MPI_COMM_WORLD)); }
  static void broadcast(void* data, int bytes) { MPI_Bcast(data, bytes, MPI_BYTE, 0, MPI_COMM_WORLD); }

 private:
  int rank_ = 0;
};

/// A call on an engine constructed after MPI was finalized: a broken contract.
FactorizationResult mpi_finalized() {
  throw InternalError("mumps-mpi: MPI was finalized before the engine was constructed");
}

}  // namespace

struct MumpsMpiFactorization::Impl {
  explicit Impl(const FactorizationOptions& options) : engine(options, WorldComm{}, "mumps-mpi") {}
  MumpsEngine<WorldComm> engine;
};

MumpsMpiFactorization::MumpsMpiFactorization(const FactorizationOptions& options) {
  if (ensure_mpi()) impl_ = std::make_unique<Impl>(options);
}

MumpsMpiFactorization::~MumpsMpiFactorization() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) {
    // MUMPS cannot release its instance without MPI any more: leak it rather than crash.
    static_cast<void>(impl_.release());
  }
}

FactorizationResult MumpsMpiFactorization::analyze(const SparseMatrix& A) {
  return impl_ ? impl_->engine.analyze(A) : mpi_finalized();
}

FactorizationResult MumpsMpiFactorization::factorize(const SparseMatrix& A) {
  return impl_ ? impl_->engine.factorize(A) : mpi_finalized();
}

FactorizationResult MumpsMpiFactorization::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const {
  return impl_ ? impl_->engine.solve(B, X) : mpi_finalized();
}

FactorizationResult MumpsMpiFactorization::schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                                            Eigen::MatrixXd* S) {
  return impl_ ? impl_->engine.schur_complement(A, block1, S) : mpi_finalized();
}

FactorizationResult MumpsMpiFactorization::solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const {
  return impl_ ? impl_->engine.solve_interior(B2, X2) : mpi_finalized();
}

double MumpsMpiFactorization::rcond_estimate() const { return impl_ ? impl_->engine.rcond_estimate() : -1.0; }

bool MumpsMpiFactorization::holds_results() const { return impl_ ? impl_->engine.is_root() : true; }

int MumpsMpiFactorization::num_processes() const { return impl_ ? mpi_size() : 1; }

int MumpsMpiFactorization::share(int value) const { return impl_ ? impl_->engine.share(value) : value; }

int MumpsMpiFactorization::num_analyses() const noexcept { return impl_ ? impl_->engine.num_analyses() : 0; }

int MumpsMpiFactorization::num_factorizations() const noexcept {
  return impl_ ? impl_->engine.num_factorizations() : 0;
}

int MumpsMpiFactorization::mpi_rank() {
  int rank = 0;
  if (ensure_mpi()) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int MumpsMpiFactorization::mpi_size() {
  int size = 1;
  if (ensure_mpi()) MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

}  // namespace hemivem
