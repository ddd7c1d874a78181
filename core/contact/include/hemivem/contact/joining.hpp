// Two bodies in contact as one linear system: the displacements of one body's contact nodes
// replaced by their displacements relative to the point of the other body across from them.
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

#include <hemivem/vem/assembly.hpp>

namespace hemivem {

/// The point of the other body across from a contact node: the combination sum_k w_k x_{q_k} of
/// up to three of its vertices (unused slots -1). At a vertex: one vertex of weight 1; on an
/// edge of a plane body: the edge's two ends; on a triangular face of a solid: its three
/// corners. The lowest-order virtual space is linear on such an edge or triangle, so the
/// displacement of that point is sum_k w_k u_{q_k} exactly.
struct Across {
  std::array<int, 3> vertex{-1, -1, -1};
  std::array<double, 3> weight{0.0, 0.0, 0.0};
  /// The vertex q itself (weight 1).
  static Across vertex_at(int q) {
    Across a;
    a.vertex[0] = q;
    a.weight[0] = 1.0;
    return a;
  }
  /// The number of vertices used.
  int size() const noexcept {
    int n = 0;
    while (n < 3 && vertex[static_cast<std::size_t>(n)] >= 0) ++n;
    return n;
  }
  /// The vertex of the largest weight (-1 for none).
  int nearest() const noexcept {
    int best = -1;
    for (int k = 0; k < size(); ++k)
      if (best < 0 || weight[static_cast<std::size_t>(k)] > weight[static_cast<std::size_t>(best)]) best = k;
    return best < 0 ? -1 : vertex[static_cast<std::size_t>(best)];
  }
};

/// The change of coordinates that joins two bodies at their contact pairs (docs/two-bodies.md).
///
/// The bodies are one mesh of two pieces (their vertices numbered together) and one linear
/// system of all their dofs. At a pair (p, a), p a contact node of one body and a the point of
/// the other body across from it (the vertex at its point, or a point of an edge or triangle:
/// Across), the coordinates of p become r = u_p - sum_k w_k u_{q_k}, the relative displacement,
/// and each q_k keeps its own: u = T v with u_p = v_p + sum_k w_k v_{q_k} and every other dof as
/// it is. The joined system is T^T A T v = T^T b over the same free dofs, so that a contact law
/// of the relative normal displacement r . nu acts on coordinates of the system as a
/// foundation's law acts on u . nu, and the condensation, the reduced problem and every engine
/// are those of one body.
///
/// Prescribed displacements: a component prescribed at some q_k and free at p leaves r free
/// (the prescribed part of the combination moved into the load); prescribed at p and at every
/// q_k, r is prescribed to g_p - sum_k w_k g_{q_k}; prescribed at p and free at some q_k it
/// cannot be one coordinate of the joined system: InputError naming the vertices.
class Joining {
 public:
  /// No pairs: the identity.
  Joining() = default;
  /// The pairs (p, a) of the system's mesh (`dim` dofs per vertex, dof d * v + c). InputError
  /// for a vertex out of range, a node p in two pairs, a vertex on both sides (a node p that is
  /// some pair's q_k), and a component prescribed at p but free at some q_k.
  Joining(const DofMap& dofs, std::vector<std::pair<int, Across>> pairs, int dim);

  bool empty() const noexcept { return pairs_.empty(); }
  const std::vector<std::pair<int, Across>>& pairs() const noexcept { return pairs_; }

  /// The joined system T^T A T v = T^T (b - A s) (s: the prescribed part of the combinations
  /// of free components), with the joined prescribed values (prescribed()).
  LinearSystem join(const LinearSystem& system);
  /// The joined load of a new load `b` of the same system with the prescribed values
  /// `prescribed` (all dofs), and those values joined in `joined_prescribed`.
  Eigen::VectorXd join_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed,
                            Eigen::VectorXd& joined_prescribed) const;
  /// True when some pair's p is free where one of its q_k is prescribed: the joined load then
  /// takes A's columns at p (join(), or set_shift_columns()).
  bool shifts_load() const noexcept { return !shifted_.empty(); }
  /// The free unknowns p of the shifted components (whose q_k include a prescribed one), in
  /// order: the columns of A that a shifted joined load takes.
  std::vector<int> shifted_unknowns() const;
  /// A's columns at shifted_unknowns() (every free row, in that order), for a joining made
  /// without the whole system (join() takes them from it). InternalError for another size.
  void set_shift_columns(SparseMatrix columns);
  /// The prescribed values of the joined system (every dof): at a prescribed p the prescribed
  /// relative displacement g_p - sum_k w_k g_{q_k}, elsewhere `prescribed`'s.
  Eigen::VectorXd join_prescribed(const Eigen::VectorXd& prescribed) const;
  /// T^T A T for a part A of the system: A(i, j) stands for the entry of the free unknowns
  /// unknowns[i] and unknowns[j] (`unknowns` increasing), T restricted to them, computed as
  /// join() computes the whole product. Its rows are the joined system's wherever A holds the
  /// whole rows and columns of that unknown and of every pair's p it is a q_k of, and every p
  /// whose row it reads has its q_k among `unknowns` (what a process reads:
  /// hemivem/contact/pose_share.hpp).
  SparseMatrix join_part(const SparseMatrix& A, const std::vector<int>& unknowns) const;
  /// T^T (b - A s) for the values b of the free unknowns `unknowns` (increasing), T restricted
  /// to them and s the prescribed part of the shifted combinations at the values `prescribed`
  /// (every dof), as join_load() computes the whole product; the same conditions.
  Eigen::VectorXd join_part(const Eigen::VectorXd& b, const std::vector<int>& unknowns,
                            const Eigen::VectorXd& prescribed) const;
  /// What the joined system's energy leaves out of the bodies': with u = T v + z (z the
  /// prescribed part of the shifted combinations at the values `prescribed`),
  /// 1/2 u.A u - u.b = 1/2 v.A_j v - v.b_j + 1/2 z.A z - z.b. The part of 1/2 z.A z - z.b of the
  /// free unknowns first, ..., first + b.size() - 1, `b` their load (0 without a shift).
  double shift_energy(const Eigen::VectorXd& b, Eigen::Index first, const Eigen::VectorXd& prescribed) const;
  /// T^-T f for values f of the free unknowns of the joined system (forces: a residual of the
  /// joined system): the same forces on the free dofs of the two bodies, f_q - sum w_k f_p at
  /// each pair's q_k. The joined residual T^T (A u - b) gives A u - b.
  Eigen::VectorXd unjoined_forces(const Eigen::VectorXd& f) const;

  /// u = T v for vectors of all dofs.
  Eigen::VectorXd displacement(const Eigen::VectorXd& v) const;
  /// v = T^-1 u for vectors of all dofs: relative displacements at the pairs.
  Eigen::VectorXd relative(const Eigen::VectorXd& u) const;

 private:
  /// T restricted to the free unknowns `unknowns` (increasing).
  SparseMatrix restricted(const std::vector<int>& unknowns) const;
  /// s: the prescribed part of each shifted combination, sum_k w_k g_{q_k} over its prescribed q_k.
  Eigen::VectorXd shift_values(const Eigen::VectorXd& prescribed) const;
  /// A z, z the free vector of the values s at the shifted components' p: the shift of the load
  /// (InternalError when A's columns at them are not known).
  Eigen::VectorXd load_shift(const Eigen::VectorXd& prescribed) const;

  std::vector<std::pair<int, Across>> pairs_;
  int num_free_ = 0, num_dofs_ = 0;  // of the system joined
  // per paired component: p's dof and free index (-1: prescribed), and the q_k's
  struct Term {
    int dof = 0, free = -1;
    double weight = 0.0;
  };
  struct Component {
    int free_p = -1, dof_p = 0;
    std::vector<Term> across;
    bool shifted = false;  // p free and some q_k prescribed
  };
  std::vector<Component> components_;
  SparseMatrix T_;            // on the free dofs: u_f = T_ v_f (+ s)
  SparseMatrix shift_;        // the columns of A at the free p-dofs some of whose q_k are prescribed
  std::vector<int> shifted_;  // their components (index into components_)
};

}  // namespace hemivem
