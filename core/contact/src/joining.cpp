#include <hemivem/contact/joining.hpp>
#include <hemivem/error.hpp>

#include <Eigen/SparseCore>

#include <string>

namespace hemivem {

Joining::Joining(const DofMap& dofs, std::vector<std::array<int, 2>> pairs, int dim)
    : pairs_(std::move(pairs)), num_free_(dofs.num_free()), num_dofs_(dofs.num_dofs()) {
  const int nv = dofs.num_dofs() / dim;
  std::vector<char> seen(static_cast<std::size_t>(nv), 0);
  for (const auto& [p, q] : pairs_) {
    for (int v : {p, q}) {
      if (v < 0 || v >= nv)
        throw InputError("contact pair (" + std::to_string(p) + ", " + std::to_string(q) + "): vertex " +
                         std::to_string(v) + " out of range (the mesh has " + std::to_string(nv) + " vertices)");
      if (seen[static_cast<std::size_t>(v)])
        throw InputError("vertex " + std::to_string(v) +
                         " is in two contact pairs: a vertex meets at most one vertex of the other body");
      seen[static_cast<std::size_t>(v)] = 1;
    }
    for (int c = 0; c < dim; ++c) {
      Component k;
      k.dof_p = dim * p + c;
      k.dof_q = dim * q + c;
      k.free_p = dofs.free_index[static_cast<std::size_t>(k.dof_p)];
      k.free_q = dofs.free_index[static_cast<std::size_t>(k.dof_q)];
      if (k.free_p < 0 && k.free_q >= 0)
        throw InputError("vertex " + std::to_string(p) + " has its " + std::string(1, "xyz"[c]) +
                         " displacement prescribed and the vertex " + std::to_string(q) +
                         " of the other body at its point has it free: the two bodies' vertices at one point of their "
                         "contact take the same supports, or the one across the contact from the prescribed one does");
      components_.push_back(k);
    }
  }
  const int n = dofs.num_free();
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(static_cast<std::size_t>(n) + components_.size());
  for (int k = 0; k < n; ++k) t.emplace_back(k, k, 1.0);
  for (std::size_t k = 0; k < components_.size(); ++k) {
    const Component& c = components_[k];
    if (c.free_p >= 0 && c.free_q >= 0) t.emplace_back(c.free_p, c.free_q, 1.0);
    if (c.free_p >= 0 && c.free_q < 0) shifted_.push_back(static_cast<int>(k));
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
  // the columns of A whose dof's partner is prescribed: b - A s for every later load
  std::vector<Eigen::Triplet<double, int>> t;
  for (std::size_t j = 0; j < shifted_.size(); ++j)
    for (SparseMatrix::InnerIterator it(system.A, components_[static_cast<std::size_t>(shifted_[j])].free_p); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), static_cast<int>(j), it.value());
  shift_.resize(system.A.rows(), static_cast<Eigen::Index>(shifted_.size()));
  shift_.setFromTriplets(t.begin(), t.end());
  joined.dofs = system.dofs;
  joined.b = join_load(system.b, system.dofs.prescribed, joined.dofs.prescribed);
  return joined;
}

Eigen::VectorXd Joining::join_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed,
                                   Eigen::VectorXd& joined_prescribed) const {
  joined_prescribed = prescribed;
  for (const Component& c : components_)
    if (c.free_p < 0) joined_prescribed(c.dof_p) = prescribed(c.dof_p) - prescribed(c.dof_q);
  Eigen::VectorXd s(static_cast<Eigen::Index>(shifted_.size()));
  for (std::size_t j = 0; j < shifted_.size(); ++j)
    s(static_cast<Eigen::Index>(j)) = prescribed(components_[static_cast<std::size_t>(shifted_[j])].dof_q);
  Eigen::VectorXd shifted = b;
  if (s.size() > 0) shifted -= shift_ * s;
  return T_.transpose() * shifted;
}

Eigen::VectorXd Joining::displacement(const Eigen::VectorXd& v) const {
  Eigen::VectorXd u = v;
  for (const Component& c : components_) u(c.dof_p) = v(c.dof_p) + v(c.dof_q);
  return u;
}

Eigen::VectorXd Joining::relative(const Eigen::VectorXd& u) const {
  Eigen::VectorXd v = u;
  for (const Component& c : components_) v(c.dof_p) = u(c.dof_p) - u(c.dof_q);
  return v;
}

}  // namespace hemivem
