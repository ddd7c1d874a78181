// The loads a path has condensed so far, so that a step whose load is a combination of them
// costs no interior solve (docs/paths.md, "What a step costs").
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace hemivem::detail {

/// Load vectors v_1, ..., v_m (each the free dofs' right-hand side followed by the prescribed
/// values) kept with an orthonormal basis Q of their span, V = Q R. coefficients(v) gives the
/// alpha with v = V alpha when v lies in the span: its distance |v - Q Q^T v| from it, computed
/// as written (not from |v|^2 - |Q^T v|^2, which would cancel), at most `tolerance` times |v|.
/// Q is kept reorthogonalised, so that the distance is measured to round-off. Two passes over
/// v and Q, each reading them once; the blocks of rows where every column of Q is zero (a load
/// on a part of the boundary leaves most rows zero) are read in v's first pass only. At most
/// `capacity` loads are kept.
class SolvedLoads {
 public:
  SolvedLoads() = default;
  SolvedLoads(Eigen::Index length, int capacity, double tolerance)
      : capacity_(capacity), tolerance_(tolerance), V_(length, 0), Q_(length, 0) {}

  int size() const noexcept { return static_cast<int>(V_.cols()); }
  bool full() const noexcept { return size() >= capacity_; }
  double tolerance() const noexcept { return tolerance_; }
  const Eigen::MatrixXd& loads() const noexcept { return V_; }

  /// The coefficients of v (none when v is not in the span; all zero when v is zero).
  std::optional<Eigen::VectorXd> coefficients(const Eigen::VectorXd& v) const;
  /// Keeps v (the caller checks full() first and that v is not in the span). Returns its index.
  int add(const Eigen::VectorXd& v);
  /// V alpha (zero without loads); with one load, alpha_1 v_1 itself.
  Eigen::VectorXd combination(const Eigen::VectorXd& alpha) const;

 private:
  // q = Q^T v and |v| (with the squares of v's blocks), in one pass; |v - Q q|, in another
  Eigen::VectorXd project(const Eigen::VectorXd& v, double* norm, std::vector<double>* squares) const;
  double distance(const Eigen::VectorXd& v, const Eigen::VectorXd& q, const std::vector<double>& squares) const;
  int capacity_ = 0;
  double tolerance_ = 0.0;
  Eigen::MatrixXd V_, Q_, R_;
  std::vector<char> nonzero_;  // per block of rows: some column of Q is nonzero there
};

}  // namespace hemivem::detail
