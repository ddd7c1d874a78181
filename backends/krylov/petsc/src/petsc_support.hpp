// Private helpers of the PETSc Krylov module (not installed): PETSc's error messages, PETSc's
// start and end in the process (PetscRuntime), its quiet error handler, and the collectives by
// which the processes of a distributed system agree on an outcome, so that every process takes
// the same path (the same status, the same exception) and none is left waiting in a collective
// call another has left.
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <petscsys.h>

#include <atomic>
#include <cstdint>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

namespace hemivem::petsc {

/// "PETSc error <code> in <call>: <message>".
inline std::string error_message(PetscErrorCode code, const char* call) {
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(static_cast<int>(code), &text, &specific);
  std::string out = "PETSc error " + std::to_string(static_cast<int>(code)) + " in " + call;
  if (text && *text) out += std::string(": ") + text;
  if (specific && *specific) out += std::string(" (") + specific + ")";
  return out;
}

/// Inside a function returning PetscErrorCode with a std::string* error: the call, and on
/// failure its message in *error and its code returned.
#define HEMIVEM_PETSC(call)                                          \
  do {                                                               \
    const PetscErrorCode hemivem_code_ = (call);                     \
    if (hemivem_code_ != 0) {                                        \
      *error = ::hemivem::petsc::error_message(hemivem_code_, #call); \
      return hemivem_code_;                                          \
    }                                                                \
  } while (0)

/// PETSc in this process: initialized once by the first object or entry point that needs it
/// (PetscInitializeNoArguments, which initializes MPI when nobody did), finalized at program
/// exit when hemivem initialized it, no object is left and MPI still runs.
class PetscRuntime {
 public:
  static PetscRuntime& instance() {
    static PetscRuntime runtime;
    return runtime;
  }

  /// Empty when PETSc runs; why it does not otherwise.
  const std::string& start() {
    std::call_once(once_, [this] {
      PetscBool initialized = PETSC_FALSE;
      if (PetscInitialized(&initialized) == 0 && initialized) return;  // the program's own PETSc
      PetscBool finalized = PETSC_FALSE;
      if (PetscFinalized(&finalized) == 0 && finalized) {
        error_ = "PETSc was finalized in this process";
        return;
      }
      // Before PetscInitialize: PETSc leaves the program's signal handlers alone.
      PetscOptionsSetValue(nullptr, "-no_signal_handler", "true");
      // GAMG's Galerkin products P^T A P by forming P^T: 40 % less time in its set-ups for about
      // a quarter more memory at the peak of a solve (docs/full-space.md); PETSC_OPTIONS, read
      // by PetscInitialize, may choose otherwise
      PetscOptionsSetValue(nullptr, "-matptap_via", "rap");
      const PetscErrorCode code = PetscInitializeNoArguments();
      if (code != 0) {
        error_ = "PetscInitialize failed with error " + std::to_string(static_cast<int>(code));
        return;
      }
      owned_ = true;
    });
    return error_;
  }

  void attach() noexcept { ++live_; }
  void detach() noexcept { --live_; }

  /// True while PETSc objects may be created and destroyed.
  static bool running() noexcept {
    PetscBool initialized = PETSC_FALSE, finalized = PETSC_TRUE;
    return PetscInitialized(&initialized) == 0 && initialized && PetscFinalized(&finalized) == 0 && !finalized;
  }

  ~PetscRuntime() {
    if (!owned_ || live_.load() > 0 || !running()) return;
    int mpi_finalized = 0;
    if (MPI_Finalized(&mpi_finalized) != MPI_SUCCESS || mpi_finalized) return;
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    PetscFinalize();
  }

 private:
  PetscRuntime() = default;

  std::once_flag once_;
  std::string error_;
  bool owned_ = false;
  std::atomic<int> live_{0};
};

/// PETSc's error handler is PetscReturnErrorHandler (nothing printed) while it lives.
class QuietErrors {
 public:
  QuietErrors() { pushed_ = PetscPushErrorHandler(PetscReturnErrorHandler, nullptr) == 0; }
  ~QuietErrors() {
    if (pushed_) PetscPopErrorHandler();
  }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  bool pushed_ = false;
};

/// While it lives, the global option "-matptap_via rap" (GAMG's Galerkin products through P^T,
/// which PetscRuntime sets for sequential matrices) is cleared, and set again at its end: PETSc's
/// MPI matrices know no such algorithm and would fail, so the distributed path runs its set-ups
/// and solves under it. Another value of the option is left alone.
class WithoutSequentialProducts {
 public:
  WithoutSequentialProducts() {
    char value[32] = {};
    PetscBool set = PETSC_FALSE;
    if (PetscOptionsGetString(nullptr, nullptr, "-matptap_via", value, sizeof(value), &set) == 0 && set &&
        std::string(value) == "rap")
      cleared_ = PetscOptionsClearValue(nullptr, "-matptap_via") == 0;
  }
  ~WithoutSequentialProducts() {
    if (cleared_) PetscOptionsSetValue(nullptr, "-matptap_via", "rap");
  }
  WithoutSequentialProducts(const WithoutSequentialProducts&) = delete;
  WithoutSequentialProducts& operator=(const WithoutSequentialProducts&) = delete;

 private:
  bool cleared_ = false;
};

inline int comm_rank(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

inline int comm_size(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  return size;
}

/// Collective over comm: the lowest rank where `here` is true; the number of ranks when it is
/// nowhere.
inline int first_rank_where(MPI_Comm comm, bool here) {
  const int size = comm_size(comm);
  const int candidate = here ? comm_rank(comm) : size;
  int first = size;
  MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, comm);
  return first;
}

/// Collective over comm: rank root's `text` on every rank.
inline std::string broadcast(MPI_Comm comm, int root, const std::string& text) {
  const bool is_root = comm_rank(comm) == root;
  int length = is_root ? static_cast<int>(text.size()) : 0;
  MPI_Bcast(&length, 1, MPI_INT, root, comm);
  std::string out = is_root ? text : std::string(static_cast<std::size_t>(length), ' ');
  MPI_Bcast(out.data(), length, MPI_CHAR, root, comm);
  return out;
}

/// " (on process <root> of <size>)" when comm has several processes, empty otherwise.
inline std::string on_process(MPI_Comm comm, int root) {
  const int size = comm_size(comm);
  return size > 1 ? " (on process " + std::to_string(root) + " of " + std::to_string(size) + ")" : std::string();
}

/// Collective over comm: the message `mine` of the lowest rank whose is not empty, on every
/// rank, followed by on_process(); empty when every rank's is.
inline std::string first_problem(MPI_Comm comm, const std::string& mine) {
  const int root = first_rank_where(comm, !mine.empty());
  if (root == comm_size(comm)) return {};
  return broadcast(comm, root, mine) + on_process(comm, root);
}

/// Collective over comm: `mine` on every rank when every rank's is success; otherwise the
/// outcome (status, and message followed by on_process()) of the lowest rank whose is not, on
/// every rank.
inline FactorizationResult agreed(MPI_Comm comm, const FactorizationResult& mine) {
  const int root = first_rank_where(comm, !mine.ok());
  if (root == comm_size(comm)) return mine;
  int status = static_cast<int>(mine.status);
  MPI_Bcast(&status, 1, MPI_INT, root, comm);
  return {static_cast<FactorizationStatus>(status), broadcast(comm, root, mine.message) + on_process(comm, root)};
}

/// Collective over comm: every rank's `count` values concatenated in the order of the ranks, on
/// every rank (counts may differ, and be 0), or with `first_only` on rank 0 alone (empty on
/// the others). Throws InternalError on every rank when the whole exceeds what MPI counts in an
/// int.
inline std::vector<double> all_gather(MPI_Comm comm, const double* data, std::int64_t count, bool first_only = false) {
  const int size = comm_size(comm);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(size), 0);
  MPI_Allgather(&count, 1, MPI_INT64_T, counts.data(), 1, MPI_INT64_T, comm);
  std::int64_t total = 0;
  for (const std::int64_t c : counts) total += c;
  if (total > std::numeric_limits<int>::max())
    throw InternalError("all_gather of " + std::to_string(total) + " values: more than MPI counts in an int");
  std::vector<int> sizes(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
  int offset = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    sizes[r] = static_cast<int>(counts[r]);
    offsets[r] = offset;
    offset += sizes[r];
  }
  if (first_only) {
    std::vector<double> all(comm_rank(comm) == 0 ? static_cast<std::size_t>(total) : 0);
    MPI_Gatherv(data, static_cast<int>(count), MPI_DOUBLE, all.data(), sizes.data(), offsets.data(), MPI_DOUBLE, 0,
                comm);
    return all;
  }
  std::vector<double> all(static_cast<std::size_t>(total));
  MPI_Allgatherv(data, static_cast<int>(count), MPI_DOUBLE, all.data(), sizes.data(), offsets.data(), MPI_DOUBLE,
                 comm);
  return all;
}

}  // namespace hemivem::petsc
