#include <hemivem/support/condition.hpp>

#include <cmath>
#include <limits>

namespace hemivem {

double norm1(const SparseMatrix& A) {
  double best = 0.0;
  for (int j = 0; j < A.outerSize(); ++j) {
    double sum = 0.0;
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) sum += std::abs(it.value());
    best = std::max(best, sum);
  }
  return best;
}

double estimate_norm1_symmetric_blocks(int n, const std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>& apply) {
  const double inf = std::numeric_limits<double>::infinity();
  if (n <= 0) return 0.0;
  bool finite = true;
  auto product = [&](const Eigen::MatrixXd& x) {
    Eigen::MatrixXd y = apply(x);
    if (y.rows() != n || y.cols() != x.cols() || !y.allFinite()) {
      finite = false;
      y.setZero(n, x.cols());
    }
    return y;
  };
  // the first block: Hager's start x = (1/n, ..., 1/n) and Higham's safeguard, a vector of
  // alternating signs and growing magnitude
  Eigen::MatrixXd first(n, 2);
  first.col(0).setConstant(1.0 / n);
  for (int i = 0; i < n; ++i) first(i, 1) = (i % 2 ? -1.0 : 1.0) * (1.0 + (n > 1 ? static_cast<double>(i) / (n - 1) : 0.0));
  const Eigen::MatrixXd y = product(first);
  double estimate = std::max(y.col(0).lpNorm<1>(), 2.0 * y.col(1).lpNorm<1>() / (3.0 * n));
  // the second block: Hager's next product B sign(y), whose largest entry bounds ||B||_inf =
  // ||B||_1 from below, with the columns of B at the largest entries of both first products
  // (where Hager's iteration would go next), each column's 1-norm a lower bound too
  Eigen::MatrixXd second = Eigen::MatrixXd::Zero(n, 3);
  second.col(0) = y.col(0).unaryExpr([](double v) { return v >= 0.0 ? 1.0 : -1.0; });
  for (Eigen::Index c = 0; c < 2; ++c) {
    Eigen::Index j = 0;
    y.col(c).cwiseAbs().maxCoeff(&j);
    second(j, c + 1) = 1.0;
  }
  const Eigen::MatrixXd z = product(second);
  estimate = std::max({estimate, z.col(0).lpNorm<Eigen::Infinity>(), z.col(1).lpNorm<1>(), z.col(2).lpNorm<1>()});
  return finite ? estimate : inf;
}

}  // namespace hemivem
