// Writing a set of output files as one transaction: a run's whole set is written into a
// temporary folder beside the target, every write is checked, and the set then replaces the
// previous one at once. A failed, interrupted or killed run never leaves a mix of two runs.
//
// Names beside an output folder DIR (in DIR's parent folder), each removed when done:
//   .DIR.hemivem-lock         the lock file (flock) held by the run writing DIR
//   .DIR.hemivem-new.PID      the set being written by process PID
//   .DIR.hemivem-ready.PID    a complete set being moved into DIR (with its manifest)
//   .DIR.hemivem-old.PID      the previous set, moved aside while the new one moves in
// A run finding such a name of a process that no longer runs finishes or undoes its work
// first: a set still being written is removed; a complete set is moved in.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace hemivem {

/// One transaction on an output folder. The constructor locks the folder (InputError
/// "another hemivem run is writing DIR" when another process holds it), finishes or removes
/// what killed runs left beside it, and makes an empty staging folder. Files are written into
/// staging() (write_file_atomically checks every write); commit() then replaces, in DIR, the
/// files named in `owned` by the staged ones: the names of `owned` the new set lacks go, any
/// other file of DIR stays. Without commit() (an exception, a signal), DIR is untouched and
/// the staging folder is removed (by the destructor, or by the next run after a kill).
class OutputTransaction {
 public:
  OutputTransaction(std::filesystem::path dir, std::vector<std::string> owned);
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  /// The output folder.
  const std::filesystem::path& dir() const { return dir_; }
  /// The folder to write the new set into (plain files, no subfolders).
  const std::filesystem::path& staging() const { return staging_; }
  /// Writes `name` into staging() through write_file_atomically. A failure is an InputError
  /// naming dir()/name and saying that dir() keeps its previous outputs.
  void write(const std::string& name, const std::function<void(std::ostream&)>& body);
  /// Runs `writes` on staging(); a WriteError it throws is rethrown naming the file in dir()
  /// and saying that dir() keeps its previous outputs.
  void stage(const std::function<void(const std::filesystem::path& staging)>& writes);
  /// Moves the staged set into dir() with SIGINT and SIGTERM held back (a signal arriving
  /// meanwhile acts once the set is in place). Returns the names of `owned` that dir() held
  /// and the new set lacks (removed). Throws InputError when the set cannot be moved in.
  std::vector<std::string> commit();

 private:
  std::filesystem::path dir_;    ///< absolute
  std::filesystem::path shown_;  ///< as given, for messages
  std::vector<std::string> owned_;
  std::filesystem::path staging_;
  int lock_fd_ = -1;
  bool committed_ = false;
};

/// How many transactions of this process have moved their set into place. A signal handler
/// may call it (it reads one std::sig_atomic_t): the command's says whether an interrupted
/// run's outputs were in place.
int committed_transactions() noexcept;

/// What a failed write of a transaction appends to its message: "DIR keeps its previous
/// outputs" (or "no outputs were written to DIR" when it held none).
std::string previous_outputs_kept(const std::filesystem::path& dir);

}  // namespace hemivem
