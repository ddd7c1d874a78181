// A contact problem: the elasticity problem and the contact boundary Gamma_3 in one or several
// parts, each with its law, gap or obstacle, constraint and friction.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/contact_law.hpp>
#include <hemivem/contact/obstacle.hpp>
#include <hemivem/reduced_problem.hpp>

namespace hemivem {

/// A friction bound that depends on the normal contact (docs/friction.md, "Coulomb's law"):
/// with it the friction law is Tresca's, j_tau = g_i |u_tau|, and the bound g_i of each node
/// is set by a fixed point within each step (hemivem/path/path.hpp):
///   - coulomb: g_i = mu p_i, p_i = (zeta_i + lambda_i) / w_i the node's contact pressure
///     (the tangential potential mu P_i |u_tau| with P_i its normal contact force);
///   - normal_displacement: g_i = h(u_nu,i), h piecewise linear through `table`'s points
///     (u_nu, h) (increasing u_nu), constant beyond the first and the last.
struct FrictionBound {
  enum class Kind { coulomb, normal_displacement };
  Kind kind = Kind::coulomb;
  double coefficient = 0.0;                  ///< coulomb: mu >= 0
  std::vector<std::array<double, 2>> table;  ///< normal_displacement: (u_nu, h >= 0) points
  /// h(u_nu) of the table (normal_displacement).
  double of_normal_displacement(double u_nu) const;
  /// The bound at a node of normal displacement u_nu and contact pressure p (negative
  /// pressures, tension, give mu * 0).
  double bound(double u_nu, double pressure) const;
};
/// "coulomb", "normal-displacement".
std::string to_string(FrictionBound::Kind kind);
/// InputError (naming `where`) for a negative or non-finite coefficient, a table with fewer
/// than one point, u_nu not increasing, or a negative or non-finite h.
void check_friction_bound(const FrictionBound& bound, const std::string& where = {});

/// How the nodes of a part that meets another body are paired with that body's surface
/// (docs/two-bodies.md): at the vertex at each node's point (the meshes matched along a contact
/// where the surfaces coincide), or at the point of the surface along each node's normal, with
/// its distance as the node's gap (surfaces that do not coincide: curved bodies touching at a
/// point, or overlapping by an interference).
enum class BodyPairing { vertex, projection };
/// "vertex", "projection".
std::string to_string(BodyPairing pairing);

/// One part of the contact boundary Gamma_3 (docs/contact-parts.md) of a plane (dim = 2) or a
/// solid (dim = 3) body: its facets (boundary edges, or boundary faces) and everything the
/// contact of its nodes obeys.
template <int dim>
struct BasicContactPart {
  using Point = PointOf<dim>;
  using ObstacleType = std::conditional_t<dim == 2, Obstacle, Obstacle3D>;
  std::string name = "contact";              ///< names the part in results
  std::vector<int> facets;                   ///< boundary edge (2D) or face (3D) ids
  std::function<double(const Point&)> gap;   ///< g >= 0 at a point of the part (empty: no gap given)
  /// A rigid obstacle instead of `gap`: each node's gap is the obstacle's gap along its normal
  /// (negative where the node starts inside, +inf where its ray misses; one-sided or no
  /// constraint only).
  std::optional<ObstacleType> obstacle;
  std::shared_ptr<const ContactLaw> law;     ///< the normal law
  ConstraintKind constraint = ConstraintKind::box;
  /// Where the normal law's origin lies. false: j acts on u_nu, its origin where the body
  /// starts (the paper's foundation: a layer of thickness g that the body compresses from the
  /// start). true: j acts on the distance to the foundation's or obstacle's surface, u_nu - g_i
  /// (normal compliance or adhesion against an obstacle: zero distance where the body meets
  /// its surface); a node whose gap is infinite (its ray misses the obstacle) never meets it
  /// and has no law. The reduced problem's normal unknowns are then those distances.
  bool law_from_surface = false;
  /// The law of the tangential displacement u_tau (friction, docs/friction.md): of u_tau in the
  /// plane, of |u_t| on a solid's surface (an even law); null: frictionless (u_tau free). A
  /// bilateral constraint without one slides freely.
  std::shared_ptr<const ContactLaw> friction;
  /// A bound that depends on the normal contact (Coulomb's law, or h(u_nu)); `friction` is
  /// then tresca_law(1) (a unit bound that each node's bound scales). None: the bound of
  /// `friction` itself (a given number, Tresca).
  std::optional<FrictionBound> friction_bound;
  /// Two bodies (docs/two-bodies.md): the facets of the other body's surface that this part's
  /// facets meet, the two bodies being pieces of one mesh. Each node of the part is paired with
  /// the vertex of these facets at its point, and the laws act on its displacement relative to
  /// that vertex's (hemivem/contact/joining.hpp). Empty: a foundation or an obstacle.
  std::vector<int> against;
  /// How the part's nodes meet `against`: at the vertex at their point, or (projection) at the
  /// point along their normal, whose distance is added to `gap` (hemivem/contact/condensation.hpp,
  /// pair_with_other_body).
  BodyPairing pairing = BodyPairing::vertex;
};
using ContactPart = BasicContactPart<2>;

/// A contact problem of a plane (dim = 2) or a solid (dim = 3) body: the elasticity problem and
/// the contact boundary Gamma_3 as a list of parts (none: no contact), e.g. a body resting on a
/// support and pressed by an indenter. Each contact node belongs to one part (a node where two
/// parts meet belongs to the one listed first).
template <int dim>
struct BasicContactProblem {
  BasicElasticityProblem<dim> elasticity;  ///< mesh, materials, loads, Gamma_1
  std::vector<BasicContactPart<dim>> parts;  ///< Gamma_3, in parts
};
using ContactProblem = BasicContactProblem<2>;

/// The parts of `problem` (problem.parts), checked (check_contact_parts). Empty without contact.
template <int dim>
std::vector<BasicContactPart<dim>> contact_parts(const BasicContactProblem<dim>& problem);

/// InputError for a part without facets or without a name, and for two parts of the same name.
template <int dim>
void check_contact_parts(const std::vector<BasicContactPart<dim>>& parts);

/// The constraint the condensation imposes on a part: its constraint, but none when it has
/// neither a gap, nor an obstacle, nor a surface of another body projected onto (bilateral
/// stays bilateral).
template <int dim>
ConstraintKind constraint_in_effect(const BasicContactPart<dim>& part) {
  const bool gapped = part.gap || part.obstacle || (!part.against.empty() && part.pairing == BodyPairing::projection);
  return part.constraint == ConstraintKind::bilateral ? ConstraintKind::bilateral
         : gapped                                     ? part.constraint
                                                      : ConstraintKind::none;
}

}  // namespace hemivem
