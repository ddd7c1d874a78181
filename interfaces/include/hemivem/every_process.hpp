// Texts across processes: a text as all_gather carries it, and an error that some processes
// meet made every process's, so that no process waits in a collective call for one that stopped.
#pragma once

#include <exception>
#include <string>

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

}  // namespace hemivem
