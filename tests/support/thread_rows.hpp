// Processes played by threads, for what a run across processes gathers (RowDistribution's
// collectives) tested in one program: all_gather hands each thread's values to all.
#pragma once

#include <barrier>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <hemivem/row_distribution.hpp>

namespace hemivem::test {

/// One of the threads of `Shared` (the processes' values meet there): its rank and one row.
class ThreadRows final : public hemivem::RowDistribution {
 public:
  struct Shared {
    explicit Shared(int size) : sync(size), values(static_cast<std::size_t>(size)), mail(static_cast<std::size_t>(size)) {}
    std::barrier<> sync;
    std::vector<Eigen::VectorXd> values;
    std::mutex mutex;  ///< guards `mail`
    std::condition_variable posted;
    std::vector<std::deque<std::vector<char>>> mail;  ///< what the first sent each, not yet taken
  };
  ThreadRows(Shared& shared, int rank) : shared_(shared), rank_(rank) {
    layout_.first = rank;
    layout_.owned = 1;
    layout_.global = size();
  }
  int rank() const override { return rank_; }
  int size() const override { return static_cast<int>(shared_.values.size()); }
  const hemivem::RowLayout& layout() const override { return layout_; }
  double sum(double value) const override { return sum_in_rank_order(Eigen::VectorXd::Constant(1, value))(0); }
  double max(double value) const override { return all_gather(Eigen::VectorXd::Constant(1, value)).maxCoeff(); }
  void update_ghosts(Eigen::VectorXd&) const override { throw std::logic_error("not used"); }
  Eigen::VectorXd all_gather(const Eigen::VectorXd& mine) const override {
    shared_.values[static_cast<std::size_t>(rank_)] = mine;
    shared_.sync.arrive_and_wait();
    Eigen::Index n = 0;
    for (const auto& v : shared_.values) n += v.size();
    Eigen::VectorXd all(n);
    n = 0;
    for (const auto& v : shared_.values) all.segment(n, v.size()) = v, n += v.size();
    shared_.sync.arrive_and_wait();  // every process has read them before the next call writes
    return all;
  }
  void send_to(int to, std::span<const char> bytes) const override {
    if (rank_ != 0 || to <= 0 || to >= size()) throw std::logic_error("send_to from another than the first");
    {
      const std::lock_guard lock(shared_.mutex);
      shared_.mail[static_cast<std::size_t>(to)].emplace_back(bytes.begin(), bytes.end());
    }
    shared_.posted.notify_all();
  }
  std::vector<char> receive_from_first() const override {
    std::unique_lock lock(shared_.mutex);
    auto& box = shared_.mail[static_cast<std::size_t>(rank_)];
    shared_.posted.wait(lock, [&] { return !box.empty(); });
    std::vector<char> bytes = std::move(box.front());
    box.pop_front();
    return bytes;
  }

 private:
  Shared& shared_;
  int rank_;
  hemivem::RowLayout layout_;
};

/// What `work(rows)` gives on each of `size` processes played by threads (rank 0 on the calling
/// thread), in the order of the ranks.
template <class Work>
auto on_threads(int size, Work&& work) {
  using Result = decltype(work(std::declval<const ThreadRows&>()));
  ThreadRows::Shared shared(size);
  std::vector<std::optional<Result>> made(static_cast<std::size_t>(size));
  const auto run = [&](int rank) {
    const ThreadRows rows(shared, rank);
    made[static_cast<std::size_t>(rank)] = work(rows);
  };
  std::vector<std::thread> others;
  for (int rank = 1; rank < size; ++rank) others.emplace_back(run, rank);
  run(0);
  for (auto& t : others) t.join();
  std::vector<Result> out;
  for (auto& m : made) out.push_back(std::move(*m));
  return out;
}

}  // namespace hemivem::test
