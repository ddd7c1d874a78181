// The contact boundary Gamma_3 and the static condensation onto its contact displacements
// (the reduced problem of hemivem/reduced_problem.hpp).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include <hemivem/vem/assembly.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/contact/joining.hpp>
#include <hemivem/contact/obstacle.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/sparse_factorization.hpp>
#include <hemivem/uniqueness.hpp>

namespace hemivem {

/// The contact nodes of Gamma_3 with their outward unit normals, nodal weights, gaps and parts.
struct ContactBoundary {
  std::vector<int> edges;   ///< boundary edge ids forming Gamma_3
  std::vector<int> nodes;   ///< contact nodes (vertex ids), nodes with prescribed displacement excluded
  std::vector<Vec2> normals;  ///< outward unit normal per contact node
  Eigen::VectorXd weights;  ///< w_i: half the lengths of the Gamma_3 edges meeting at node i
  Eigen::VectorXd gaps;     ///< g_i
  /// Per node: -1 when both displacement components are free; 0 (x) or 1 (y) when that
  /// component is prescribed and tangential to the node's normal (a roller or a symmetry line
  /// meeting Gamma_3); the normal is then exactly perpendicular to it.
  std::vector<int> prescribed_component;
  /// Per node: the index of its contact part (contact_parts order); empty: every node is in
  /// part 0.
  std::vector<int> part;
  /// 3 for a boundary of a polyhedral mesh (make_contact_boundary): `faces` instead of
  /// `edges`, the normals in `normals3d` (`normals` empty) and per node the mask of its
  /// prescribed components (bit c for component c, all tangential) in `prescribed_mask`.
  int dimension = 2;
  std::vector<int> faces;
  std::vector<Vec3> normals3d;
  std::vector<int> prescribed_mask;
  /// Per node whose part meets another body (BasicContactPart::against): the point of the other
  /// body across from it (the vertex at its point, or with BodyPairing::projection the point of
  /// its surface along the node's normal); empty (no vertex) where there is none. Empty when
  /// no part meets another body. The condensation joins the bodies at these pairs
  /// (hemivem/contact/joining.hpp): the node's unknowns are its displacements relative to
  /// that point's.
  std::vector<Across> across;

  int size() const noexcept { return static_cast<int>(nodes.size()); }
  /// The part of node i (0 when `part` is empty).
  int part_of(int i) const noexcept { return part.empty() ? 0 : part[static_cast<std::size_t>(i)]; }
  /// The partner of node i: the vertex of the largest weight in its point across (the vertex
  /// at its point when the meshes match); -1 for none.
  int partner_of(int i) const noexcept { return across.empty() ? -1 : across[static_cast<std::size_t>(i)].nearest(); }
  /// Normal displacements (N u)_i of a full nodal displacement vector.
  Eigen::VectorXd normal_displacements(const Eigen::VectorXd& u) const;
};

/// Builds Gamma_3 from boundary edges. The normal of a node is the length-weighted mean of
/// the outward normals of its Gamma_3 edges, normalised (exact on each straight segment; at a
/// corner between edges of lengths l1 and l2 it is (l1 n1 + l2 n2) normalised, which is the
/// bisector only when l1 = l2). Nodes whose displacement is prescribed (on Gamma_1) are
/// excluded. A node with one prescribed component is kept when that component is tangential
/// (|nu . e| <= tangential_tolerance), or nearly so on a symmetry line (both its contact edges
/// on one side of the line through it normal to e, |nu . e| <= symmetry_tolerance: a curved
/// Gamma_3 meeting the line): its normal is then taken exactly perpendicular to it; an oblique
/// prescribed component is an InputError.
/// `gap` gives g at a node position (constant gaps: a lambda returning a constant); a
/// negative or non-finite gap is an InputError. With an `obstacle` the gaps are
/// obstacle->gap(x, nu) instead: any value but NaN.
/// How far from tangential (|nu . e|, e the prescribed direction) a prescribed component of a
/// contact node may be.
inline constexpr double tangential_tolerance = 1e-8;
/// How far from tangential a prescribed component of a contact node on a symmetry plane may be:
/// a node whose contact facets all lie on one side of the plane through it normal to the
/// prescribed component (where a curved contact surface meets a symmetry plane or line) takes the
/// normal of the surface and its mirror image, the normal less that component, when
/// |nu . e| <= symmetry_tolerance (about 14 degrees); a larger one is refused as oblique.
inline constexpr double symmetry_tolerance = 0.25;

ContactBoundary make_contact_boundary(const Mesh& mesh, const std::vector<int>& edges, const DofMap& dofs,
                                      const std::function<double(const Vec2&)>& gap,
                                      const Obstacle* obstacle = nullptr);

/// The same for a boundary in several parts (contact_parts), each with its gap or obstacle:
/// the nodes of all parts' edges as one boundary, in the same order, with the same normals
/// and weights as make_contact_boundary of all the edges together, and per node its part.
/// A node where two parts meet (the end of one part's edges and the start of the next's)
/// belongs to the part listed first; its normal and weight still come from all its contact
/// edges, and its gap from its own part. An edge in two parts is an InputError naming both;
/// a part whose gap function is empty has gap 0.
ContactBoundary make_contact_boundary(const Mesh& mesh, const std::vector<ContactPart>& parts, const DofMap& dofs);

/// Pairs each node of `boundary` whose part meets another body (BasicContactPart::against)
/// with the point of that body's surface across from it (boundary.across):
///   - BodyPairing::vertex: the vertex of `against` at its point, within 1e-9 of the mesh's
///     size. InputError naming the part and the node when there is none (the two bodies'
///     meshes do not match along the contact: hemivem/mesh/interface.hpp matches them), or when
///     two nodes find the same vertex.
///   - BodyPairing::projection: the first point of `against` that the line through the node
///     along its normal meets (the least distance |s|, either way), on an edge of a plane body
///     or a triangular face of a solid (InputError naming a face of more corners: the virtual
///     space is linear on a triangle only); s is added to the node's gap (negative where the
///     bodies overlap). A node whose line misses every facet of `against` has no pair and the
///     gap +inf: it never meets the other body.
/// InputError when a vertex found is itself a node of the contact. The plane's and the solid's
/// make_contact_boundary call it.
template <int dim>
void pair_with_other_body(const MeshOf<dim>& mesh, const std::vector<BasicContactPart<dim>>& parts,
                          ContactBoundary& boundary);

/// The tangent frame of a solid's contact node with unit normal nu: t1 = e x nu normalised for
/// the axis e least aligned with nu, and t2 = nu x t1 (the condensation's tangential slots).
inline std::array<Vec3, 2> tangent_frame(const Vec3& nu) {
  int e = 0;
  for (int c = 1; c < 3; ++c)
    if (std::abs(nu(c)) < std::abs(nu(e))) e = c;
  const Vec3 t1 = Vec3::Unit(e).cross(nu).normalized();
  return {t1, nu.cross(t1)};
}

/// What the condensation imposes on the nodes of one contact part (ContactBoundary::part).
struct PartConditions {
  std::shared_ptr<const ContactLaw> law;             ///< the normal law (unused by a bilateral part)
  ConstraintKind constraint = ConstraintKind::none;  ///< as imposed (constraint_in_effect)
  std::shared_ptr<const ContactLaw> friction;        ///< null: frictionless
  bool law_from_surface = false;                     ///< ContactProblem::law_from_surface
};

/// The conditions of each part: its laws, its constraint in effect (constraint_in_effect)
/// and law_from_surface.
template <int dim>
std::vector<PartConditions> part_conditions(const std::vector<BasicContactPart<dim>>& parts) {
  std::vector<PartConditions> out;
  out.reserve(parts.size());
  for (const auto& p : parts) out.push_back({p.law, constraint_in_effect(p), p.friction, p.law_from_surface});
  return out;
}

/// The condensed problem and what back-substitution needs.
class Condensation {
 public:
  /// Rotates the contact-node dofs of `system` to (normal, tangential) components, orders
  /// the contact unknowns first and computes S, c with `factorization.schur_complement`; the
  /// factorization keeps A22 for back_substitute(). The contact unknowns are the normal
  /// displacements (law `law`, bounds of `constraint` and the gaps) and, with a `friction` law,
  /// the tangential displacements after them (law `friction`, no bounds): the reduced problem's
  /// coordinate-wise form (docs/friction.md). A bilateral constraint (u_nu = 0) leaves the
  /// tangential displacements only (law `friction`, or j = 0 without one). Throws NumericalError with the
  /// engine's message when the engine fails numerically (not_positive_definite,
  /// numerical_failure, out_of_memory); an InternalError of the engine (a broken contract)
  /// passes through; back_substitute() does the same.
  /// With an engine across processes (every process constructs a Condensation, see
  /// hemivem/process_group.hpp) S, c and the margin exist on the process holding
  /// the results; elsewhere reduced() has empty S and c and the margin is NaN.
  ///
  /// `law_from_surface` (ContactProblem::law_from_surface): the normal unknowns are the
  /// distances a_i = u_nu,i - g_i to the surface where the gap is finite (the reduced problem
  /// F(a + g): c - S g, bounds shifted by -g; the law unchanged), and a node with an infinite
  /// gap gets the zero law; origin() gives g per coordinate, back_substitute() adds it.
  ///
  /// `semi_coercive`: A itself is singular (rigid motions only the contact holds, see
  /// hemivem/contact/supports.hpp), A22 is not, and S is positive semidefinite. The engine then
  /// factorizes A + rho E11 (rho, the largest diagonal entry of A11, added to the diagonal of
  /// block 1 only), which is positive definite; its Schur complement is exactly S + rho I,
  /// and rho is subtracted from the result's diagonal. A21, A22 and so c and back-substitution
  /// are untouched: the solution is the same, S differs from the unshifted one by round-off of
  /// the order of eps rho.
  Condensation(const LinearSystem& system, const ContactBoundary& boundary,
               std::unique_ptr<SparseFactorization> factorization, std::shared_ptr<const ContactLaw> law,
               ConstraintKind constraint, std::shared_ptr<const ContactLaw> friction = nullptr,
               bool semi_coercive = false, bool law_from_surface = false);

  /// A boundary in several parts: node i has the conditions parts[boundary.part_of(i)], so
  /// that each node has a normal unknown unless its part is bilateral and a tangential one
  /// when its part has a friction law or is bilateral (law zero without one). The
  /// coordinates are ordered as above, all normal unknowns (in node order), then all tangential
  /// ones; normal_coordinate() and tangential_coordinate() give each node's. The reduced
  /// problem's laws hold each distinct law (by pointer) once: the normal coordinates' laws in
  /// order of first use, then the tangential ones', then the zero law of nodes that never meet
  /// their surface. With one part this is the constructor above, to the bit.
  Condensation(const LinearSystem& system, const ContactBoundary& boundary,
               std::unique_ptr<SparseFactorization> factorization, const std::vector<PartConditions>& parts,
               bool semi_coercive = false);

  /// The tag of the construction that poses without condensing.
  struct PoseOnly {};
  /// Poses the reduced problem's coordinates, laws, weights and bounds as the constructor above
  /// does, without a factorization: S stays empty and c is zero, and the rotated system of all free
  /// unknowns is kept instead (rotated_matrix(), rotated_load()) for the full-space route
  /// (hemivem/contact/full_space.hpp). Nothing that needs the factorization may be called
  /// (factorization(), back_substitute(), condition_estimate(): InternalError).
  Condensation(const LinearSystem& system, const ContactBoundary& boundary, const std::vector<PartConditions>& parts,
               PoseOnly);

  /// The tag of the construction that poses the coordinates alone.
  struct CoordinatesOnly {};
  /// The system's columns at the given free unknowns (every free row, in that order), for a
  /// posing that does not hold the system.
  using SystemColumns = std::function<SparseMatrix(const std::vector<int>& unknowns)>;
  /// Poses what PoseOnly poses but the rotated system, from the dof map alone: the coordinates,
  /// their laws, weights, bounds, origins and rows (rotated_index()), the tied rows and the
  /// contact nodes' frames (a cost of the contact surface). rotated_matrix() and rotated_load()
  /// stay empty; rotate_part() rotates a part of the system assembled elsewhere (a process's
  /// rows, hemivem/contact/pose_share.hpp). Nothing that needs the system or a factorization may
  /// be called. Two bodies (ContactBoundary::across) are joined at their pairs as PoseOnly joins
  /// them (Joining), rotate_part() joining the part too. Where a pair's node is free and a
  /// vertex across from it prescribed (Joining::shifts_load), the joined load takes the system's
  /// columns at those nodes, which `columns` gives (InputError, naming the node, without it).
  /// `dofs` becomes the posing's own (dof_map()).
  Condensation(DofMap dofs, const ContactBoundary& boundary, const std::vector<PartConditions>& parts,
               CoordinatesOnly, const SystemColumns& columns = {});

  /// A := Q^T A Q for a part A of the system of one body (of two joined bodies Q^T T^T A T Q, T
  /// restricted to the part: Joining::join_part, with its conditions on the part): A(i, j)
  /// stands for the system's entry of the free unknowns unknowns[i] and unknowns[j] (`unknowns`
  /// increasing), the result in the same numbering. Computed as the posing computes
  /// rotated_matrix(), on A's pattern (exact zeros dropped in the plane): its entry (i, j) is
  /// rotated_matrix()'s to the bit wherever A holds the system's entries in every row and column
  /// of the unknowns of i's node (as the part assemble_rows makes holds them for its owned rows).
  /// In place: one body's part is rotated in its own storage, beside a cost of the contact
  /// surface. InternalError when `unknowns` holds some but not all of a contact node's free dofs.
  void rotate_part(SparseMatrix& A, const std::vector<int>& unknowns) const;
  /// Q^T b (Q^T T^T (b - A s) for two joined bodies: Joining::join_part at the prescribed
  /// values posed) for the values b of the free unknowns `unknowns` (increasing), as
  /// rotated_load() is computed; the same InternalError.
  Eigen::VectorXd rotated_part(const Eigen::VectorXd& b, const std::vector<int>& unknowns) const;

  const ReducedProblem& reduced() const noexcept { return reduced_; }
  /// The posed construction's system of all free unknowns, in the (normal, tangential) frame at
  /// the contact nodes (and relative at the pairs of two bodies): A~ and b~ (empty after a
  /// condensation, which does not keep them).
  const SparseMatrix& rotated_matrix() const noexcept { return At_; }
  const Eigen::VectorXd& rotated_load() const noexcept { return bt_; }
  /// The index in the rotated system of reduced coordinate k (its normal or tangential slot).
  int rotated_index(Eigen::Index k) const { return block1_[static_cast<std::size_t>(coordinate1_[static_cast<std::size_t>(k)])]; }
  /// The rotated unknowns held at 0 that are not coordinates: the normals of bilateral nodes.
  std::vector<int> tied_rows() const;
  /// The full nodal displacement (prescribed values included) of the rotated free unknowns x~.
  Eigen::VectorXd displacement_of(Eigen::VectorXd xt) const;
  /// The rotated free unknowns of a full nodal displacement u (its free part, relative at the
  /// pairs, in the contact nodes' frames): displacement_of's inverse on the free dofs.
  Eigen::VectorXd rotated_free(const Eigen::VectorXd& u) const;
  /// The rotated free unknowns first, ..., first + count - 1 of u (rotated_free(u)'s segment, to
  /// the bit, without the others: a process's own rows), a range holding every free dof of each
  /// contact node it holds one of (InternalError otherwise, and for a range outside the unknowns).
  Eigen::VectorXd rotated_free(const Eigen::VectorXd& u, Eigen::Index first, Eigen::Index count) const;
  /// The forces v~ of the rotated free unknowns (a residual of the rotated system) on the
  /// unrotated free dofs: Q v~ for one body (the frames are orthogonal, so a residual of the
  /// rotated system gives the unrotated system's), T^-T Q v~ for two joined bodies
  /// (Joining::unjoined_forces). InternalError for a vector of another size.
  Eigen::VectorXd unrotated_free(const Eigen::VectorXd& vt) const;
  /// A uf for the free values uf of one body (no pairs of two bodies), A the matrix this was
  /// posed from (PoseOnly), read from the rotated matrix (Q A~ Q^T uf): the system's own matrix
  /// is no longer needed once posed. InternalError for two bodies or a condensed problem.
  Eigen::VectorXd unrotated_product(const Eigen::VectorXd& uf) const;
  /// The dof map of the posed unknowns: the system's, its prescribed values those of the load
  /// posed last (of two joined bodies, joined: Joining::join_prescribed).
  const DofMap& dof_map() const noexcept { return dofs_; }
  /// True when two bodies are joined at pairs (the rotated system is the joined one).
  bool joins_bodies() const noexcept { return !joining_.empty(); }
  /// The rigid motions the supports leave free and the contact alone holds (a semi-coercive
  /// problem, hemivem/contact/supports.hpp), as rotated free unknowns (rotated_free() of their
  /// nodal displacements), one column each; no columns where the supports hold the body. Set by
  /// whoever poses the problem for the full-space route, which proves from them that E is bounded
  /// below (hemivem/existence.hpp) and keeps its Newton systems definite along them.
  const Eigen::MatrixXd& free_motions() const noexcept { return free_motions_; }
  void set_free_motions(Eigen::MatrixXd rotated) { free_motions_ = std::move(rotated); }
  /// The part of the free unknowns first, ..., first + b.size() - 1 (`b` their unjoined load)
  /// of what the joined system's energy leaves out of the bodies' (Joining::shift_energy, at
  /// the prescribed values posed): 0 for one body and without a shift.
  double shift_energy(const Eigen::VectorXd& b, Eigen::Index first) const {
    return joining_.empty() ? 0.0 : joining_.shift_energy(b, first, dofs_.prescribed());
  }
  /// Per reduced coordinate, the normal displacement where it is 0: g_i for the normal
  /// unknowns with law_from_surface, else 0 (so u_nu = a + origin).
  const Eigen::VectorXd& origin() const noexcept { return origin_; }
  /// lambda_min(S - diag(alpha_i w_i)) as measure_uniqueness() reports it (hemivem/uniqueness.hpp:
  /// exactly 0 within round-off): F is strongly convex when positive; -inf for a law with a
  /// concave kink. reduced().uniqueness_roundoff is its round-off bound.
  double uniqueness_margin() const noexcept { return margin_; }
  /// Widens the margin's round-off bound by the condensation's own, eps * kappa * ||S||_1 for
  /// an estimate kappa of A22's condition number (hemivem::widen_uniqueness_roundoff).
  void widen_uniqueness_roundoff(double kappa);
  /// The coordinate of the reduced problem that is contact node i's normal (tangential)
  /// displacement, or -1 when it is not an unknown (bilateral; frictionless).
  int normal_coordinate(int node) const noexcept { return coordinate(normal_coordinate_, node); }
  int tangential_coordinate(int node) const noexcept { return coordinate(tangential_coordinate_, node); }
  /// A solid's node with both tangential displacements unknown: the coordinate of the second
  /// (along slot_direction(node, 2)); the pair is a group of the reduced problem, the friction
  /// law acting on its norm. -1 in the plane and where a tangential component is prescribed.
  int second_tangential_coordinate(int node) const noexcept { return coordinate(second_tangential_coordinate_, node); }
  /// The unit direction (x, y, z; z = 0 in the plane) of contact node i's slot s: 0 its normal,
  /// 1 the tangential of tangential_coordinate(), 2 that of second_tangential_coordinate().
  Vec3 slot_direction(int node, int slot) const;
  /// Full nodal displacement (all 2*num_vertices dofs, prescribed values included) from
  /// a point a of the reduced problem (the contact unknowns): u2 = A22^{-1} (b2 - A21 a) (one
  /// backward substitution where the engine splits the interior solve).
  /// Collective with an engine across processes: a is read, and u returned, on the process
  /// holding the results; elsewhere a is ignored and the result is empty.
  Eigen::VectorXd back_substitute(const Eigen::VectorXd& a) const;
  /// The point of the reduced problem a full nodal displacement u (2*num_vertices entries)
  /// stands for: per contact node its normal displacement u . nu_i (less origin()) and, with
  /// tangential unknowns, u . tau_i. A start for the minimizer from a displacement known
  /// otherwise (the previous step of an adaptive solve). InputError for a u of the wrong size.
  Eigen::VectorXd reduced_point(const Eigen::VectorXd& u) const;
  /// A new load on the same matrix (a step of a loading history): `b` the load of the free
  /// dofs (LinearSystem::b at the new data, prescribed values lifted) and `prescribed` every
  /// dof's prescribed value (DofMap::prescribed; free dofs ignored). c is condensed again (one
  /// interior solve; collective with an engine across processes) and back_substitute() uses
  /// the new load and prescribed values. S, the laws and the margin do not change. Posed
  /// without condensation (PoseOnly), rotated_load() and displacement_of() take the new load and
  /// prescribed values (no solve).
  void set_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed);
  /// New prescribed values of a posing of one body's coordinates alone (CoordinatesOnly), as
  /// set_load() sets them, for a load whose rows are rotated elsewhere (rotated_part(): a
  /// process's rows, FullSpaceShares): `values` holds the prescribed dofs' (DofMap::free_index
  /// < 0) in dof order. InternalError for two joined bodies (set_load() joins their values),
  /// for a posing that holds a system or a factorization, and for another count of values.
  void set_prescribed_values(const Eigen::VectorXd& values);
  /// New gaps of the contact nodes (a moving obstacle or gap; one per node, bilateral nodes'
  /// unused): the bounds of the normal unknowns (each under its part's constraint), and with
  /// law_from_surface their origin, c, and the zero law for a node whose gap is infinite (its
  /// part's law again once it is finite). InputError for a NaN gap.
  void set_gaps(const Eigen::VectorXd& gaps);
  /// c before the shift by -S origin(): the condensed load b1 - A12 A22^{-1} b2 (of the
  /// reduced coordinates) on the process holding the results.
  const Eigen::VectorXd& condensed_load() const noexcept { return raw_c_; }
  const SparseFactorization& factorization() const;
  /// Estimate of the 1-norm condition number kappa_1(A22) of the factorized interior block,
  /// independent of the engine: ||A22||_1 times the Hager-Higham estimate of ||A22^{-1}||_1
  /// from 3 interior solves, the first of two right-hand sides (the same calls on every
  /// process). +inf when a solve fails.
  double condition_estimate() const;

 private:
  DofMap dofs_;
  Joining joining_;  // two bodies: their pairs (empty: one body)
  std::unique_ptr<SparseFactorization> factorization_;
  ReducedProblem reduced_;
  double margin_ = 0.0;
  bool semi_coercive_ = false;
  Eigen::VectorXd origin_;
  // per contact node: its coordinates (-1: none), constraint and whether its law acts from the surface
  std::vector<int> normal_coordinate_, tangential_coordinate_, second_tangential_coordinate_;
  std::vector<ConstraintKind> constraint_;
  std::vector<char> from_surface_;
  std::shared_ptr<const ContactLaw> zero_;  // the law j = 0 of the coordinates that need one
  Eigen::VectorXi law_at_start_;  // each coordinate's law where its gap is finite (law_from_surface)
  Eigen::VectorXd raw_c_;         // condensed_load()
  std::vector<int> block1_;       // rotated free index of block 1: every node's normal, then the tangentials
  std::vector<int> coordinate1_;  // the position in block 1 of each reduced coordinate
  std::vector<int> block2_;       // remaining rotated free indices, increasing (condensed only)
  // Per contact node, the rotation of its free dofs: m free components at the free indices
  // idx[0..m) (in component order); slot j (the normal for j = 0, then the tangentials) lives at
  // idx[j], and the dofs are u(idx[r]) = sum_j C(r, j) u~(idx[j]); `full` holds the slots'
  // directions in all d components (column j), for the reduced point of a displacement.
  struct NodeFrame {
    int m = 0;
    std::array<int, 3> idx{-1, -1, -1};
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d full = Eigen::Matrix3d::Zero();
  };
  int dimension_ = 2;
  std::vector<NodeFrame> frames_;
  /// Whether the rotation keeps A's pattern, exact zeros included (in 3D).
  bool keeps_pattern() const noexcept;
  /// The frames of the contact nodes whose free dofs are among `unknowns` (increasing), their
  /// indices the positions there.
  std::vector<NodeFrame> frames_in(const std::vector<int>& unknowns) const;
  /// Q^T b for the frames `frames` (their indices b's).
  static Eigen::VectorXd rotate_vector(const Eigen::VectorXd& b, const std::vector<NodeFrame>& frames);
  std::vector<int> nodes_;        // vertex of each contact node
  static int coordinate(const std::vector<int>& of, int node) noexcept {
    return node >= 0 && node < static_cast<int>(of.size()) ? of[static_cast<std::size_t>(node)] : -1;
  }
  // the steps of the constructor, in order
  void pose(const LinearSystem& system, const ContactBoundary& boundary, const std::vector<PartConditions>& parts,
            SparseMatrix* At, Eigen::VectorXd* bt);
  void pose_coordinates(const DofMap& dofs, const ContactBoundary& boundary, const std::vector<PartConditions>& parts);
  void number_coordinates(const ContactBoundary& boundary, const std::vector<PartConditions>& parts);
  void order_unknowns(const DofMap& dofs, const ContactBoundary& boundary);
  void order_interior();
  Eigen::VectorXd rotate_load(const Eigen::VectorXd& b) const;
  void measure_interior(const SparseMatrix& At);
  void pose_reduced_problem(const ContactBoundary& boundary, const std::vector<PartConditions>& parts);
  void measure_from_surface(const ContactBoundary& boundary);
  void compute_schur_complement(const SparseMatrix& At);
  void condense_load(const Eigen::VectorXd& bt);
  void take_load(Eigen::VectorXd bt);
  // the steps of back_substitute()
  Eigen::VectorXd block1_values(const Eigen::VectorXd& a) const;
  Eigen::VectorXd displacement(const Eigen::VectorXd& x1, const Eigen::VectorXd& u2) const;
  Eigen::VectorXd from_rotated(Eigen::VectorXd ut) const;
  /// The free values in x, y[, z] of rotated free values (Q ut).
  Eigen::VectorXd unrotate(Eigen::VectorXd ut) const;
  /// A21_ = At(block2, block1), for an engine that does not split the interior solve.
  void extract_a21(const SparseMatrix& At);
  SparseMatrix A21_;              // block2 x block1 of the rotated matrix (when extracted)
  double a22_norm1_ = 0.0;        // ||A22||_1
  Eigen::VectorXd b2_;
  SparseMatrix At_;     // the rotated system (PoseOnly)
  Eigen::MatrixXd free_motions_;
  Eigen::VectorXd bt_;
};

}  // namespace hemivem
