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

double estimate_norm1_symmetric_blocks(int n, const std::function<Eigen::MatrixXd(const Eigen::MatrixXd&)>& apply,
                                       int iterations) {
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
  // Higham's safeguard: a vector of alternating signs and growing magnitude, solved with the
  // first iterate
  Eigen::MatrixXd first(n, 2);
  first.col(0).setConstant(1.0 / n);
  for (int i = 0; i < n; ++i) first(i, 1) = (i % 2 ? -1.0 : 1.0) * (1.0 + (n > 1 ? static_cast<double>(i) / (n - 1) : 0.0));
  const Eigen::MatrixXd y0 = product(first);
  double estimate = std::max(y0.col(0).lpNorm<1>(), 2.0 * y0.col(1).lpNorm<1>() / (3.0 * n));
  Eigen::VectorXd y = y0.col(0);  // B x
  for (int it = 1; it < iterations; ++it) {
    const Eigen::VectorXd sign = y.unaryExpr([](double v) { return v >= 0.0 ? 1.0 : -1.0; });
    const Eigen::VectorXd z = product(sign).col(0);  // B^T sign(y) = B sign(y): B is symmetric
    Eigen::Index j = 0;
    z.cwiseAbs().maxCoeff(&j);
    y = product(Eigen::VectorXd::Unit(n, j)).col(0);  // the next x is e_j
    estimate = std::max(estimate, y.lpNorm<1>());
  }
  return finite ? estimate : inf;
}

double estimate_norm1_symmetric(int n, const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& apply,
                                int iterations) {
  return estimate_norm1_symmetric_blocks(
      n,
      [&](const Eigen::MatrixXd& x) {
        Eigen::MatrixXd y(x.rows(), x.cols());
        for (Eigen::Index k = 0; k < x.cols(); ++k) {
          const Eigen::VectorXd column = apply(x.col(k));
          if (column.size() != x.rows()) return Eigen::MatrixXd();
          y.col(k) = column;
        }
        return y;
      },
      iterations);
}

}  // namespace hemivem
