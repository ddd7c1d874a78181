#include "solved_loads.hpp"

#include <hemivem/error.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace hemivem::detail {

namespace {
constexpr Eigen::Index block = 4096;  // entries per block: v's and Q's blocks stay in cache
}  // namespace

Eigen::VectorXd SolvedLoads::project(const Eigen::VectorXd& v, double* norm, std::vector<double>* squares) const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(Q_.cols());
  double sum = 0.0;
  squares->clear();
  for (Eigen::Index i = 0, k = 0; i < v.size(); i += block, ++k) {
    const Eigen::Index n = std::min(block, v.size() - i);
    squares->push_back(v.segment(i, n).squaredNorm());
    sum += squares->back();
    // a block where every load kept is zero adds exact zeros to q
    if (nonzero_[static_cast<std::size_t>(k)]) q.noalias() += Q_.middleRows(i, n).transpose() * v.segment(i, n);
  }
  *norm = std::sqrt(sum);
  return q;
}

double SolvedLoads::distance(const Eigen::VectorXd& v, const Eigen::VectorXd& q, const std::vector<double>& squares) const {
  double sum = 0.0;
  Eigen::VectorXd r;
  for (Eigen::Index i = 0, k = 0; i < v.size(); i += block, ++k) {
    // where Q's block is zero, v's block is the residual's: its squares are known
    if (!nonzero_[static_cast<std::size_t>(k)]) {
      sum += squares[static_cast<std::size_t>(k)];
      continue;
    }
    const Eigen::Index n = std::min(block, v.size() - i);
    r.noalias() = v.segment(i, n) - Q_.middleRows(i, n) * q;
    sum += r.squaredNorm();
  }
  return std::sqrt(sum);
}

std::optional<Eigen::VectorXd> SolvedLoads::coefficients(const Eigen::VectorXd& v) const {
  if (v.size() != V_.rows()) throw InternalError("SolvedLoads::coefficients: a load of another size");
  if (size() == 0) {
    if (v.isZero(0.0)) return Eigen::VectorXd();
    return std::nullopt;
  }
  double norm = 0.0;
  std::vector<double> squares;
  const Eigen::VectorXd q = project(v, &norm, &squares);
  if (norm == 0.0) return Eigen::VectorXd(Eigen::VectorXd::Zero(size()));
  if (!(distance(v, q, squares) <= tolerance_ * norm)) return std::nullopt;
  return Eigen::VectorXd(R_.triangularView<Eigen::Upper>().solve(q));
}

int SolvedLoads::add(const Eigen::VectorXd& v) {
  if (full()) throw InternalError("SolvedLoads::add beyond its capacity");
  if (v.size() != V_.rows()) throw InternalError("SolvedLoads::add: a load of another size");
  // Gram-Schmidt twice against Q
  const Eigen::Index m = V_.cols();
  Eigen::VectorXd r = v;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m);
  for (int pass = 0; pass < 2 && m > 0; ++pass) {
    const Eigen::VectorXd dq = Q_.transpose() * r;
    r.noalias() -= Q_ * dq;
    q += dq;
  }
  const double norm = r.norm();
  if (!(norm > 0.0)) throw InternalError("SolvedLoads::add: a load in the span of those kept");
  V_.conservativeResize(Eigen::NoChange, m + 1);
  Q_.conservativeResize(Eigen::NoChange, m + 1);
  R_.conservativeResize(m + 1, m + 1);
  V_.col(m) = v;
  Q_.col(m) = r / norm;
  nonzero_.resize(static_cast<std::size_t>((v.size() + block - 1) / block), 0);
  for (Eigen::Index i = 0, k = 0; i < v.size(); i += block, ++k)
    if (!Q_.col(m).segment(i, std::min(block, v.size() - i)).isZero(0.0)) nonzero_[static_cast<std::size_t>(k)] = 1;
  R_.row(m).setZero();
  R_.col(m).head(m) = q;
  R_(m, m) = norm;
  return static_cast<int>(m);
}

Eigen::VectorXd SolvedLoads::combination(const Eigen::VectorXd& alpha) const {
  if (alpha.size() != V_.cols()) throw InternalError("SolvedLoads::combination: wrong number of coefficients");
  if (alpha.size() == 0) return Eigen::VectorXd::Zero(V_.rows());
  if (alpha.size() == 1) return alpha(0) * V_.col(0);
  return V_ * alpha;
}

}  // namespace hemivem::detail
