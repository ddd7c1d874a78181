// The motion of a group of two coordinates whose law acts on their norm (a solid's isotropic
// friction: ReducedProblem::groups) within one projected Newton iteration: the ssn engine's on
// the reduced problem and the full-space route's (hemivem/contact/full_space.hpp) in the whole
// space classify a group, send it onto a knot in radius and move it along the projection arc
// by these functions.
#pragma once

#include <Eigen/Core>

#include <limits>

#include <hemivem/contact_law.hpp>

namespace hemivem {

/// x scaled onto radius `radius` > 0 (x != 0), its entries then moved by single ulps until
/// hypot(x) == radius where a few such moves reach it: a norm that is exactly a kink is the
/// kink for every later test (the certificate's too), a norm one ulp off is not.
Eigen::Vector2d onto_radius(const Eigen::Vector2d& x, double radius);

/// What an iteration knows about one group, in the radial frame e = v / |v| (at v = 0: the
/// direction it leaves along) and t = e turned a quarter counter-clockwise. Its radius is
/// confined to the piece [r_lo, r_hi] between the neighbouring knots in radius (the kinks of j,
/// and 0 where j'(0+) > 0).
struct GroupMotion {
  enum class Mode {
    stuck,  ///< at v = 0 with 0 in its subdifferential disc: no motion
    ray,    ///< at v = 0, leaving along e: the one unknown is its length along e
    held,   ///< on a positive kink with the radial force in the Clarke interval: moves along the circle
    plane,  ///< r > 0 inside its piece: both directions (e, t) are unknowns
  };
  Mode mode = Mode::stuck;
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  ///< the pair's values
  Eigen::Vector2d e = Eigen::Vector2d::Zero(), t = Eigen::Vector2d::Zero();
  Eigen::Vector2d grad = Eigen::Vector2d::Zero();  ///< the gradient of the objective on the side of motion
  double r = 0.0;
  double r_lo = 0.0, r_hi = 0.0;
  bool lo_is_knot = false;            ///< r_lo is a kink of j(|v|) (0 only where j'(0+) > 0)
  double radial_curvature = 0.0;      ///< w j''(r, side)
  double tangential_curvature = 0.0;  ///< w j'(r, side) / r
  double scale = 1.0;                 ///< of the gradient steps
  /// The radius the Newton direction sends it onto (NaN: none).
  double pin = std::numeric_limits<double>::quiet_NaN();
};

/// The motion of a group of law w j(|v|) at v, where the smooth part of the objective has the
/// gradient `smooth_gradient` on the pair and the 2 x 2 block `smooth_hessian` (for the scale of
/// its gradient steps): stuck, leaving 0 along a ray, held on a positive kink, or moving in its
/// piece of radius, with the gradient and curvatures on the side of motion.
GroupMotion group_motion(const ContactLaw& law, double w, const Eigen::Vector2d& v,
                         const Eigen::Vector2d& smooth_gradient, const Eigen::Matrix2d& smooth_hessian);

/// The epsilon-active set of a group: pins it onto the knot in radius it is pushed against when
/// it is within eps of it (onto 0 only where 0 is a knot); leaves pin NaN otherwise.
void pin_group(GroupMotion& g, double eps);

/// The group's point on the projection arc at step t along its direction dg: the radius kept in
/// the piece [r_lo, r_hi] by radial scaling; at v = 0 the length along the ray in [0, r_hi]; a
/// group whose piece starts at the cone point 0 goes exactly onto 0 when the step crosses the
/// line through 0 normal to e; a pinned group's radius goes linearly to its pin, a group pinned
/// onto 0 goes onto it at any step (it is within eps of it, and at 0 its frame is renewed).
Eigen::Vector2d group_trial(const GroupMotion& g, const Eigen::Vector2d& dg, double t);

}  // namespace hemivem
