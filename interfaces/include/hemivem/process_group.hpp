// The processes an engine runs on, for engines that run across processes (mumps-mpi under
// mpirun). An engine in one process implements SparseFactorization alone; an engine across
// processes implements ProcessGroup as well, and the callers that must keep every process on
// the same path (the static condensation, the contact solver, the command) ask
// processes_of(engine).
//
// With an engine across processes every call of the engine is collective: the engine is
// constructed on every process and every method is called on every process in the same order;
// the matrices and right-hand sides are read on one process and the outputs (X, X2, S) are
// written there only. What the callers do with those outputs runs there only too, through
// run_where_results_are(), which keeps every process on the same path when it fails.
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <exception>
#include <string>

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

  /// Collective: runs `work` on the process holding the results only, then tells every
  /// process how it ended. When `work` throws there, the exception is rethrown there and
  /// every other process throws an error of the same kind (InputError, NumericalError, else
  /// Error) saying that the process holding the results reports it; no process is left
  /// waiting in the next collective call.
  template <class Work>
  void run_where_results_are(Work&& work) const {
    int outcome = kCompleted;
    std::exception_ptr failure;
    if (holds_results()) {
      try {
        work();
      } catch (const InputError&) {
        failure = std::current_exception();
        outcome = kThrewInputError;
      } catch (const NumericalError&) {
        failure = std::current_exception();
        outcome = kThrewNumericalError;
      } catch (...) {
        failure = std::current_exception();
        outcome = kThrewOther;
      }
    }
    outcome = share(outcome);
    if (failure) std::rethrow_exception(failure);
    if (outcome != kCompleted) throw_elsewhere(outcome);
  }

 private:
  static constexpr int kCompleted = 0;
  static constexpr int kThrewInputError = -1;
  static constexpr int kThrewNumericalError = -2;
  static constexpr int kThrewOther = -3;

  [[noreturn]] static void throw_elsewhere(int outcome) {
    const std::string what = "the process holding the results failed (it reports the error)";
    if (outcome == kThrewInputError) throw InputError(what);
    if (outcome == kThrewNumericalError) throw NumericalError(what);
    throw Error(what);
  }
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
