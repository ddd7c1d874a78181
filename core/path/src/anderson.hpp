// Anderson's acceleration of a fixed point x <- G(x) (Walker and Ni 2011, "Anderson acceleration
// for fixed-point iterations"): the next iterate mixes the last few so that the combination of
// their residuals f = G(x) - x is least in the 2-norm.
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>

#include <deque>

namespace hemivem::detail {

class AndersonMixing {
 public:
  explicit AndersonMixing(int depth) : depth_(depth) {}

  /// The next iterate from x and its residual f = G(x) - x, with the relaxation theta:
  /// x + theta f - (dX + theta dF) gamma, gamma minimising |f - dF gamma| over the last `depth`
  /// differences dX, dF of iterates and residuals (x + theta f without history).
  Eigen::VectorXd next(const Eigen::VectorXd& x, const Eigen::VectorXd& f, double theta) {
    if (x_.size() == x.size()) {
      dx_.push_back(x - x_);
      df_.push_back(f - f_);
      if (static_cast<int>(dx_.size()) > depth_) {
        dx_.pop_front();
        df_.pop_front();
      }
    }
    x_ = x;
    f_ = f;
    Eigen::VectorXd out = x + theta * f;
    if (dx_.empty()) return out;
    const auto k = static_cast<Eigen::Index>(dx_.size());
    Eigen::MatrixXd DX(x.size(), k), DF(x.size(), k);
    for (Eigen::Index j = 0; j < k; ++j) {
      DX.col(j) = dx_[static_cast<std::size_t>(j)];
      DF.col(j) = df_[static_cast<std::size_t>(j)];
    }
    const Eigen::VectorXd gamma = DF.colPivHouseholderQr().solve(f);
    if (!gamma.allFinite()) return out;
    out -= (DX + theta * DF) * gamma;
    return out;
  }

  /// Forgets the history (after an iterate whose residual grew).
  void restart() {
    dx_.clear();
    df_.clear();
    x_.resize(0);
  }

 private:
  int depth_;
  Eigen::VectorXd x_, f_;
  std::deque<Eigen::VectorXd> dx_, df_;
};

}  // namespace hemivem::detail
