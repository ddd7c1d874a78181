// The rows of a system distributed over processes (MPI_COMM_WORLD under mpirun), as the
// full-space route (hemivem/contact/full_space.hpp) and its Krylov engines read them: each
// process owns a contiguous range of the global rows, in the order of the processes' ranks, and
// reads the values of some rows owned by others (its ghosts). A process holds
//   - its owned rows of a matrix, with local column numbers: its owned rows first (local column
//     c is global row first + c), then its ghosts in the order of layout().ghosts;
//   - vectors of its owned entries, or of its owned entries followed by its ghosts'.
// In one process (OneProcessRows) every row is owned, there are no ghosts, and every collective
// returns its argument. Every collective method is called by every process in the same order.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/error.hpp>

namespace hemivem {

/// Which rows a process owns and which others it reads.
struct RowLayout {
  Eigen::Index first = 0;   ///< the global index of its first owned row
  Eigen::Index owned = 0;   ///< it owns the rows first, ..., first + owned - 1
  Eigen::Index global = 0;  ///< the rows of all processes
  /// The global indices of the rows of other processes it reads, increasing; ghost i is local
  /// column (and vector entry) owned + i.
  std::vector<Eigen::Index> ghosts;
};

class RowDistribution {
 public:
  virtual ~RowDistribution() = default;
  /// This process's rank and the number of processes.
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual const RowLayout& layout() const = 0;
  /// Collective: the sum, and the largest, of `value` over the processes.
  virtual double sum(double value) const = 0;
  virtual double max(double value) const = 0;
  /// Collective: `v` (layout().owned entries, then one per ghost) gets its ghosts' entries from
  /// the processes that own them; its owned entries are unchanged. Called by every process, also
  /// by one without ghosts (its owned entries may be another's ghosts).
  virtual void update_ghosts(Eigen::VectorXd& v) const = 0;
  /// Collective: every process's `mine` (of any size, possibly none) concatenated in the order of
  /// the ranks, on every process; of the owned entries of a vector, the whole vector.
  virtual Eigen::VectorXd all_gather(const Eigen::VectorXd& mine) const = 0;
  /// Collective: all_gather's concatenation on the first process alone (empty on the others),
  /// for what only it needs, such as the rows of a file it writes.
  virtual Eigen::VectorXd gather_to_first(const Eigen::VectorXd& mine) const {
    Eigen::VectorXd all = all_gather(mine);
    return rank() == 0 ? all : Eigen::VectorXd();
  }

  /// From the first process to process `to` (another): `bytes`, which process `to` takes by
  /// receive_from_first(), as many times and in the order the first sends to it (each send
  /// waits until its bytes may be taken; a process waits in receive_from_first until they come).
  /// One process has none to send to: InternalError.
  virtual void send_to(int to, std::span<const char> /*bytes*/) const {
    throw InternalError("send_to(" + std::to_string(to) + ") in a run of " + std::to_string(size()) + " process(es)");
  }
  virtual std::vector<char> receive_from_first() const {
    throw InternalError("receive_from_first() in a run of " + std::to_string(size()) + " process(es)");
  }
  /// Collective: the first process's `bytes` into every other process's `bytes` (what each held
  /// before replaced). By default the first sends them to each in turn (send_to); a distribution
  /// over MPI sends them along a tree (MPI_Bcast), so that the first sends about as much whatever
  /// the number of processes.
  virtual void broadcast_from_first(std::vector<char>& bytes) const {
    if (size() == 1) return;
    if (rank() == 0)
      for (int to = 1; to < size(); ++to) send_to(to, bytes);
    else
      bytes = receive_from_first();
  }

  double min(double value) const { return -max(-value); }
  /// Collective: the sum of every process's `mine` (of one length on all), added in the order of
  /// the ranks, so that every process gets the same bits.
  Eigen::VectorXd sum_in_rank_order(const Eigen::VectorXd& mine) const {
    const Eigen::VectorXd all = all_gather(mine);
    if (all.size() != mine.size() * size()) throw InternalError("the processes' sums differ in length");
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(mine.size());
    for (Eigen::Index at = 0; at < all.size(); at += mine.size()) sum += all.segment(at, mine.size());
    return sum;
  }
  /// The number of local columns: owned rows and ghosts.
  Eigen::Index columns() const { return layout().owned + static_cast<Eigen::Index>(layout().ghosts.size()); }
};

/// The share of process `rank` of `size` in an even split of `count` items in their order: the
/// items [first, end), first = count * rank / size (rounded down), so that every process's share
/// differs from another's by at most one item and the shares follow the ranks. The caller checks
/// 0 <= rank < size and count >= 0.
inline std::pair<Eigen::Index, Eigen::Index> even_share(Eigen::Index count, int rank, int size) {
  const auto at = [&](int r) { return static_cast<Eigen::Index>(static_cast<long long>(count) * r / size); };
  return {at(rank), at(rank + 1)};
}

/// The share [first, end) of `count` items that this process of `processes` takes (even_share);
/// all of them with no processes.
inline std::pair<std::size_t, std::size_t> share_of(std::size_t count, const RowDistribution* processes) {
  if (!processes) return {0, count};
  const auto [first, end] = even_share(static_cast<Eigen::Index>(count), processes->rank(), processes->size());
  return {static_cast<std::size_t>(first), static_cast<std::size_t>(end)};
}

/// One process owning all `n` rows.
class OneProcessRows final : public RowDistribution {
 public:
  explicit OneProcessRows(Eigen::Index n) { layout_.owned = layout_.global = n; }
  int rank() const override { return 0; }
  int size() const override { return 1; }
  const RowLayout& layout() const override { return layout_; }
  double sum(double value) const override { return value; }
  double max(double value) const override { return value; }
  void update_ghosts(Eigen::VectorXd&) const override {}
  Eigen::VectorXd all_gather(const Eigen::VectorXd& mine) const override { return mine; }

 private:
  RowLayout layout_;
};

}  // namespace hemivem
