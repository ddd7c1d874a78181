// Two bodies in contact as one linear system: the displacements of one body's contact nodes
// replaced by their displacements relative to the other body's nodes they are paired with.
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

#include <hemivem/vem/assembly.hpp>

namespace hemivem {

/// The change of coordinates that joins two bodies at their contact pairs (docs/two-bodies.md).
///
/// The bodies are one mesh of two pieces (their vertices numbered together) and one linear
/// system of all their dofs. At a pair (p, q), p a contact node of one body and q the vertex of
/// the other body at the same point, the coordinates of p become r = u_p - u_q, the relative
/// displacement, and q keeps u_q: u = T v with u_p = v_p + v_q and every other dof as it is. The
/// joined system is T^T A T v = T^T b over the same free dofs, so that a contact law of the
/// relative normal displacement r . nu acts on coordinates of the system as a foundation's law
/// acts on u . nu, and the condensation, the reduced problem and every engine are those of one
/// body.
///
/// Prescribed displacements: a component prescribed at q and free at p leaves r free (u_p = r +
/// g_q, g_q moved into the load); prescribed at both, r is prescribed to g_p - g_q; prescribed
/// at p alone it cannot be one coordinate of the joined system: InputError naming the vertices.
class Joining {
 public:
  /// No pairs: the identity.
  Joining() = default;
  /// The pairs (p, q) of vertices of the system's mesh (`dim` dofs per vertex, dof d * v + c).
  /// InputError for a vertex out of range, a vertex in two pairs or on both sides, and a
  /// component prescribed at p but free at q.
  Joining(const DofMap& dofs, std::vector<std::array<int, 2>> pairs, int dim);

  bool empty() const noexcept { return pairs_.empty(); }
  const std::vector<std::array<int, 2>>& pairs() const noexcept { return pairs_; }

  /// The joined system T^T A T v = T^T (b - A s) (s: the prescribed values of the partners of
  /// free components), with the joined prescribed values (prescribed()).
  LinearSystem join(const LinearSystem& system);
  /// The joined load of a new load `b` of the same system with the prescribed values
  /// `prescribed` (all dofs), and those values joined in `joined_prescribed`.
  Eigen::VectorXd join_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed,
                            Eigen::VectorXd& joined_prescribed) const;
  /// u = T v for vectors of all dofs.
  Eigen::VectorXd displacement(const Eigen::VectorXd& v) const;
  /// v = T^-1 u for vectors of all dofs: relative displacements at the pairs.
  Eigen::VectorXd relative(const Eigen::VectorXd& u) const;

 private:
  std::vector<std::array<int, 2>> pairs_;
  int num_free_ = 0, num_dofs_ = 0;  // of the system joined
  // per paired component: (free index of p's dof or -1, dof of p, dof of q)
  struct Component {
    int free_p = -1, free_q = -1, dof_p = 0, dof_q = 0;
  };
  std::vector<Component> components_;
  SparseMatrix T_;       // on the free dofs: u_f = T_ v_f (+ s)
  SparseMatrix shift_;   // the columns of A at the free p-dofs whose q is prescribed
  std::vector<int> shifted_;  // their components (index into components_)
};

}  // namespace hemivem
