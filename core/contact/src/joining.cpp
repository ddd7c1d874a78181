#include <hemivem/contact/joining.hpp>
#include <hemivem/error.hpp>

#include <Eigen/SparseCore>

#include <algorithm>
#include <string>

namespace hemivem {

Joining::Joining(const DofMap& dofs, std::vector<std::pair<int, Across>> pairs, int dim)
    : pairs_(std::move(pairs)), num_free_(dofs.num_free()), num_dofs_(dofs.num_dofs()) {
  const int nv = dofs.num_dofs() / dim;
  // 1: a node p, 2: some pair's q_k
  std::vector<char> role(static_cast<std::size_t>(nv), 0);
  const auto in_range = [&](int v, int p) {
    if (v < 0 || v >= nv)
      throw InputError("contact pair of node " + std::to_string(p) + ": vertex " + std::to_string(v) +
                       " out of range (the mesh has " + std::to_string(nv) + " vertices)");
  };
  for (const auto& [p, across] : pairs_) {
    in_range(p, p);
    if (role[static_cast<std::size_t>(p)] == 1)
      throw InputError("vertex " + std::to_string(p) +
                       " is in two contact pairs: a node meets one point of the other body");
    role[static_cast<std::size_t>(p)] = 1;
  }
  for (const auto& [p, across] : pairs_)
    for (int k = 0; k < across.size(); ++k) {
      const int q = across.vertex[static_cast<std::size_t>(k)];
      in_range(q, p);
      if (role[static_cast<std::size_t>(q)] == 1)
        throw InputError("vertex " + std::to_string(q) + " is a contact node and across from node " +
                         std::to_string(p) + ": a surface meets another body from one side only");
    }
  for (const auto& [p, across] : pairs_)
    for (int c = 0; c < dim; ++c) {
      Component k;
      k.dof_p = dim * p + c;
      k.free_p = dofs.free_index(k.dof_p);
      for (int j = 0; j < across.size(); ++j) {
        Term t;
        t.dof = dim * across.vertex[static_cast<std::size_t>(j)] + c;
        t.free = dofs.free_index(t.dof);
        t.weight = across.weight[static_cast<std::size_t>(j)];
        if (k.free_p < 0 && t.free >= 0)
          throw InputError(
              "vertex " + std::to_string(p) + " has its " + std::string(1, "xyz"[c]) +
              " displacement prescribed and the vertex " + std::to_string(t.dof / dim) +
              " of the other body across from it has it free: the two bodies' vertices at one point of "
              "their contact take the same supports, or the one across the contact from the prescribed one does");
        if (k.free_p >= 0 && t.free < 0) k.shifted = true;
        k.across.push_back(t);
      }
      components_.push_back(std::move(k));
    }
  const int n = dofs.num_free();
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(static_cast<std::size_t>(n) + 3 * components_.size());
  for (int k = 0; k < n; ++k) t.emplace_back(k, k, 1.0);
  for (std::size_t k = 0; k < components_.size(); ++k) {
    const Component& c = components_[k];
    if (c.free_p < 0) continue;
    for (const Term& q : c.across)
      if (q.free >= 0) t.emplace_back(c.free_p, q.free, q.weight);
    if (c.shifted) shifted_.push_back(static_cast<int>(k));
  }
  T_.resize(n, n);
  T_.setFromTriplets(t.begin(), t.end());
}

LinearSystem Joining::join(const LinearSystem& system) {
  if (system.dofs.num_free() != num_free_ || system.dofs.num_dofs() != num_dofs_)
    throw InputError("a joined system needs " + std::to_string(num_free_) + " free dofs, got " +
                     std::to_string(system.dofs.num_free()));
  LinearSystem joined;
  const SparseMatrix TA = SparseMatrix(T_.transpose()) * system.A;
  joined.A = TA * T_;
  // the columns of A whose dof's combination has a prescribed part: b - A s for every later load
  std::vector<Eigen::Triplet<double, int>> t;
  for (std::size_t j = 0; j < shifted_.size(); ++j)
    for (SparseMatrix::InnerIterator it(system.A, components_[static_cast<std::size_t>(shifted_[j])].free_p); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), static_cast<int>(j), it.value());
  shift_.resize(system.A.rows(), static_cast<Eigen::Index>(shifted_.size()));
  shift_.setFromTriplets(t.begin(), t.end());
  joined.dofs = system.dofs;
  Eigen::VectorXd joined_prescribed;
  joined.b = join_load(system.b, system.dofs.prescribed(), joined_prescribed);
  joined.dofs.set_prescribed_values(joined.dofs.prescribed_part(joined_prescribed));
  return joined;
}

Eigen::VectorXd Joining::join_prescribed(const Eigen::VectorXd& prescribed) const {
  Eigen::VectorXd joined = prescribed;
  for (const Component& c : components_)
    if (c.free_p < 0)
      for (const Term& q : c.across) joined(c.dof_p) -= q.weight * prescribed(q.dof);
  return joined;
}

Eigen::VectorXd Joining::shift_values(const Eigen::VectorXd& prescribed) const {
  Eigen::VectorXd s(static_cast<Eigen::Index>(shifted_.size()));
  for (std::size_t j = 0; j < shifted_.size(); ++j) {
    double value = 0.0;
    for (const Term& q : components_[static_cast<std::size_t>(shifted_[j])].across)
      if (q.free < 0) value += q.weight * prescribed(q.dof);
    s(static_cast<Eigen::Index>(j)) = value;
  }
  return s;
}

Eigen::VectorXd Joining::load_shift(const Eigen::VectorXd& prescribed) const {
  if (shift_.cols() != static_cast<Eigen::Index>(shifted_.size()) || shift_.rows() != num_free_)
    throw InternalError("the columns of a joined load shifted by prescribed values are not known");
  return shift_ * shift_values(prescribed);
}

double Joining::shift_energy(const Eigen::VectorXd& b, Eigen::Index first, const Eigen::VectorXd& prescribed) const {
  if (shifted_.empty()) return 0.0;
  const Eigen::VectorXd s = shift_values(prescribed);
  const Eigen::VectorXd Az = load_shift(prescribed);
  double energy = 0.0;
  for (std::size_t j = 0; j < shifted_.size(); ++j) {
    const int p = components_[static_cast<std::size_t>(shifted_[j])].free_p;
    if (p < first || p >= first + b.size()) continue;
    const double z = s(static_cast<Eigen::Index>(j));
    energy += z * (0.5 * Az(p) - b(p - first));
  }
  return energy;
}

Eigen::VectorXd Joining::join_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed,
                                   Eigen::VectorXd& joined_prescribed) const {
  joined_prescribed = join_prescribed(prescribed);
  Eigen::VectorXd shifted = b;
  if (!shifted_.empty()) shifted -= load_shift(prescribed);
  return T_.transpose() * shifted;
}

std::vector<int> Joining::shifted_unknowns() const {
  std::vector<int> out;
  for (const int k : shifted_) out.push_back(components_[static_cast<std::size_t>(k)].free_p);
  return out;
}

void Joining::set_shift_columns(SparseMatrix columns) {
  if (columns.rows() != num_free_ || columns.cols() != static_cast<Eigen::Index>(shifted_.size()))
    throw InternalError("the columns of a shifted joined load need " + std::to_string(num_free_) + " rows and " +
                        std::to_string(shifted_.size()) + " columns");
  shift_ = std::move(columns);
}

namespace {

/// The position of free unknown f in `unknowns` (increasing), -1 when it is not there.
int position(const std::vector<int>& unknowns, int f) {
  const auto at = std::lower_bound(unknowns.begin(), unknowns.end(), f);
  return at != unknowns.end() && *at == f ? static_cast<int>(at - unknowns.begin()) : -1;
}

}  // namespace

SparseMatrix Joining::restricted(const std::vector<int>& unknowns) const {
  const auto n = static_cast<int>(unknowns.size());
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) t.emplace_back(k, k, 1.0);
  for (const Component& c : components_) {
    if (c.free_p < 0) continue;
    const int p = position(unknowns, c.free_p);
    if (p < 0) continue;
    for (const Term& q : c.across)
      if (const int l = q.free >= 0 ? position(unknowns, q.free) : -1; l >= 0) t.emplace_back(p, l, q.weight);
  }
  SparseMatrix T(n, n);
  T.setFromTriplets(t.begin(), t.end());
  return T;
}

SparseMatrix Joining::join_part(const SparseMatrix& A, const std::vector<int>& unknowns) const {
  const SparseMatrix T = restricted(unknowns);
  if (A.rows() != T.rows() || A.cols() != T.cols()) throw InternalError("a part of the system of another size than its unknowns");
  const SparseMatrix TA = SparseMatrix(T.transpose()) * A;
  return TA * T;
}

Eigen::VectorXd Joining::join_part(const Eigen::VectorXd& b, const std::vector<int>& unknowns,
                                   const Eigen::VectorXd& prescribed) const {
  const SparseMatrix T = restricted(unknowns);
  if (b.size() != T.rows()) throw InternalError("a part of a load of another size than its unknowns");
  if (shifted_.empty()) return T.transpose() * b;
  const Eigen::VectorXd shift = load_shift(prescribed);
  Eigen::VectorXd shifted = b;
  for (std::size_t k = 0; k < unknowns.size(); ++k) shifted(static_cast<Eigen::Index>(k)) -= shift(unknowns[k]);
  return T.transpose() * shifted;
}

Eigen::VectorXd Joining::unjoined_forces(const Eigen::VectorXd& f) const {
  if (f.size() != num_free_)
    throw InternalError("unjoined forces need " + std::to_string(num_free_) + " values, got " + std::to_string(f.size()));
  Eigen::VectorXd out = f;
  for (const Component& c : components_) {
    if (c.free_p < 0) continue;
    for (const Term& q : c.across)
      if (q.free >= 0) out(q.free) -= q.weight * f(c.free_p);
  }
  return out;
}

Eigen::VectorXd Joining::displacement(const Eigen::VectorXd& v) const {
  Eigen::VectorXd u = v;
  for (const Component& c : components_)
    for (const Term& q : c.across) u(c.dof_p) += q.weight * v(q.dof);
  return u;
}

Eigen::VectorXd Joining::relative(const Eigen::VectorXd& u) const {
  Eigen::VectorXd v = u;
  for (const Component& c : components_)
    for (const Term& q : c.across) v(c.dof_p) -= q.weight * u(q.dof);
  return v;
}

}  // namespace hemivem
