// Texts across processes: a text as all_gather carries it, an error that some processes meet
// made every process's, so that no process waits in a collective call for one that stopped, and
// what the first process makes for each of the others sent to it.
#pragma once

#include <exception>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <hemivem/error.hpp>
#include <hemivem/row_distribution.hpp>

namespace hemivem {

namespace detail {

/// A text as values of a vector (one byte each), and back: what all_gather carries.
inline Eigen::VectorXd bytes_of(const std::string& text) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(text.size()));
  for (std::size_t k = 0; k < text.size(); ++k) v(static_cast<Eigen::Index>(k)) = static_cast<unsigned char>(text[k]);
  return v;
}
inline std::string text_of(const Eigen::VectorXd& v) {
  std::string text(static_cast<std::size_t>(v.size()), ' ');
  for (Eigen::Index k = 0; k < v.size(); ++k) text[static_cast<std::size_t>(k)] = static_cast<char>(static_cast<int>(v(k)));
  return text;
}

}  // namespace detail

/// Collective over `rows`: `work()` on every process. When it throws on some, every process
/// throws: those its own error, every other an InputError with the first such process's
/// message, so that no process goes on to wait for one that stopped.
template <class Work>
auto on_every_process(const RowDistribution& rows, Work&& work) -> decltype(work()) {
  decltype(work()) out{};
  std::exception_ptr failed;
  std::string why;
  try {
    out = work();
  } catch (const std::exception& e) {
    failed = std::current_exception();
    why = e.what();
  }
  const Eigen::VectorXd flags = rows.all_gather(Eigen::VectorXd::Constant(1, failed ? 1.0 : 0.0));
  Eigen::Index first = 0;
  while (first < flags.size() && flags(first) == 0.0) ++first;
  if (first == flags.size()) return out;
  const std::string message =
      detail::text_of(rows.all_gather(detail::bytes_of(rows.rank() == first ? why : std::string())));
  if (failed) std::rethrow_exception(failed);
  throw InputError("process " + std::to_string(first) + " stopped: " + message);
}

/// Collective over `rows`: the value the first process makes for this one. On the first,
/// `make(deliver)` makes every process's value in turn and calls `deliver(r, value)` once for
/// each process r (its own among them); each other process's value is sent to it at once, as
/// `write(value, bytes)` appends it to bytes, and read back there by `read(bytes)` (so the first
/// holds one other's value at a time). When `make` (or a `write`) throws on the first, every
/// process it has not sent to throws InputError "process 0 stopped: <its message>" and the first
/// rethrows its own; the processes it had sent to return theirs (a caller's on_every_process
/// then ends every process). A value delivered twice, or none for a process: InternalError on
/// the first (the others as above).
template <class T, class Make, class Write, class Read>
T made_by_first(const RowDistribution& rows, Make&& make, Write&& write, Read&& read) {
  constexpr char kMade = 'm', kStopped = 's';
  if (rows.rank() != 0) {
    const std::vector<char> bytes = rows.receive_from_first();
    if (!bytes.empty() && bytes[0] == kMade) return read(std::span<const char>(bytes).subspan(1));
    throw InputError("process 0 stopped: " + std::string(bytes.begin() + (bytes.empty() ? 0 : 1), bytes.end()));
  }
  const auto size = static_cast<std::size_t>(rows.size());
  std::vector<char> made(size, 0), sent(size, 0);
  std::optional<T> own;
  try {
    make([&](int r, T&& value) {
      const auto at = static_cast<std::size_t>(r);
      if (r < 0 || at >= size || made[at])
        throw InternalError("a value made for process " + std::to_string(r) + " of " + std::to_string(size) +
                            (r >= 0 && at < size ? " twice" : ""));
      made[at] = 1;
      if (r == 0) {
        own = std::move(value);
        return;
      }
      std::vector<char> bytes{kMade};
      write(value, bytes);
      rows.send_to(r, bytes);
      sent[at] = 1;
    });
    for (std::size_t r = 0; r < size; ++r)
      if (!made[r]) throw InternalError("no value made for process " + std::to_string(r));
  } catch (const std::exception& e) {
    const std::string why = e.what();
    std::vector<char> bytes{kStopped};
    bytes.insert(bytes.end(), why.begin(), why.end());
    for (std::size_t r = 1; r < size; ++r)
      if (!sent[r]) rows.send_to(static_cast<int>(r), bytes);
    throw;
  }
  return std::move(*own);
}

}  // namespace hemivem
