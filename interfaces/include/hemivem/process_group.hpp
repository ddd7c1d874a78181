// The processes an engine runs on, for engines that run across processes (mumps-mpi under
// mpirun). An engine in one process implements SparseFactorization alone; an engine across
// processes implements ProcessGroup as well, and the callers that must keep every process on
// the same path (the static condensation, the contact solver, the command) ask
// processes_of(engine).
//
// With an engine across processes every call of the engine is collective: the engine is
// constructed on every process and every method is called on every process in the same order;
// the matrices and right-hand sides are read on one process and the outputs (X, X2, S) are
// written there only.
#pragma once

#include <hemivem/sparse_factorization.hpp>

namespace hemivem {

class ProcessGroup {
 public:
  virtual ~ProcessGroup() = default;

  /// True on the process that receives the outputs.
  virtual bool holds_results() const = 0;
  /// The number of processes the engine runs on.
  virtual int num_processes() const = 0;
  /// Collective: every process returns the `value` given on the process that holds the
  /// results, so that work done there alone can decide the path every process takes next.
  virtual int share(int value) const = 0;
};

/// One process: it holds the results, and share() returns its argument.
class SingleProcess final : public ProcessGroup {
 public:
  bool holds_results() const override { return true; }
  int num_processes() const override { return 1; }
  int share(int value) const override { return value; }
};

/// The processes `engine` runs on: the engine itself when it is a ProcessGroup, one process
/// otherwise.
inline const ProcessGroup& processes_of(const SparseFactorization& engine) {
  static const SingleProcess single;
  const auto* group = dynamic_cast<const ProcessGroup*>(&engine);
  return group != nullptr ? *group : single;
}

}  // namespace hemivem
