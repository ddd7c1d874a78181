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

double estimate_norm1_symmetric(int n, const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& apply,
                                int iterations) {
  const double inf = std::numeric_limits<double>::infinity();
  if (n <= 0) return 0.0;
  bool finite = true;
  auto product = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd y = apply(x);
    if (y.size() != n || !y.allFinite()) {
      finite = false;
      y.setZero(n);
    }
    return y;
  };
  double estimate = 0.0;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(n, 1.0 / n);
  for (int it = 0; it < iterations; ++it) {
    const Eigen::VectorXd y = product(x);
    estimate = std::max(estimate, y.lpNorm<1>());
    const Eigen::VectorXd sign = y.unaryExpr([](double v) { return v >= 0.0 ? 1.0 : -1.0; });
    const Eigen::VectorXd z = product(sign);  // B^T sign(y) = B sign(y): B is symmetric
    Eigen::Index j = 0;
    z.cwiseAbs().maxCoeff(&j);
    x.setZero();
    x(j) = 1.0;
  }
  // Higham's safeguard: a vector of alternating signs and growing magnitude.
  Eigen::VectorXd alt(n);
  for (int i = 0; i < n; ++i) alt(i) = (i % 2 ? -1.0 : 1.0) * (1.0 + (n > 1 ? static_cast<double>(i) / (n - 1) : 0.0));
  estimate = std::max(estimate, 2.0 * product(alt).lpNorm<1>() / (3.0 * n));
  return finite ? estimate : inf;
}

}  // namespace hemivem
