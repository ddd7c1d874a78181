// Piecewise-polynomial contact laws defined by breakpoints, with their DC split.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/contact_law.hpp>

namespace hemivem {

/// Coefficients of a polynomial in r, lowest degree first: c0 + c1 r + c2 r^2 + ...
using Polynomial = std::vector<double>;

/// A law given on the pieces (-inf, b0], (b0, b1], ..., (b_{m-1}, +inf) of sorted
/// breakpoints b0 < ... < b_{m-1} by the two convex parts j1 and j2 (j = j1 - j2).
/// Pieces are polynomials of degree <= 3. Validated when built: finite coefficients,
/// strictly increasing breakpoints, continuity of j1 and j2 (hence j) at every breakpoint,
/// convexity of j1 and j2 (non-negative second derivative on every piece, no downward
/// jump of the derivative at a breakpoint). Violations throw InputError naming the
/// breakpoint or piece.
class PiecewisePolynomialLaw final : public ContactLaw {
 public:
  PiecewisePolynomialLaw(std::string name, std::vector<double> breakpoints, std::vector<Polynomial> j1,
                         std::vector<Polynomial> j2);
  /// The same from the potential j and the first convex part j1 (j2 = j1 - j).
  static PiecewisePolynomialLaw from_potential(std::string name, std::vector<double> breakpoints,
                                               std::vector<Polynomial> j, std::vector<Polynomial> j1);

  /// The same from the potential j alone (continuous, pieces of degree <= 3): the DC split is
  /// computed. j2 takes (a) at every concave kink b_k (j' drops by d_k > 0) the ramp
  /// d_k (r - b_k)^+, and (b) on every piece k the constant curvature
  /// c_k = max(0, -min j'' over the piece), carried on with a continuous derivative; j2 is zero
  /// left of the first breakpoint where piece 0 is convex. Then j2 is convex (j2' does not
  /// decrease) and j1 = j + j2 is convex (j1'' = j'' + c_k >= 0 on every piece, no downward jump
  /// of j1'). InputError naming the piece or breakpoint for a j that is not continuous, or whose
  /// curvature is unbounded below on an unbounded piece (no convex split exists).
  static PiecewisePolynomialLaw from_j(std::string name, std::vector<double> breakpoints, std::vector<Polynomial> j);

  std::string name() const override { return name_; }
  double value(LawPart part, double r) const override;
  double derivative(LawPart part, double r, int side) const override;
  double second_derivative(LawPart part, double r, int side) const override;
  std::vector<double> breakpoints() const override { return breaks_; }
  double alpha() const override { return alpha_; }
  using ContactLaw::value;

  /// The pieces of a part (size breakpoints().size() + 1).
  std::vector<Polynomial> pieces(LawPart part) const;

 private:
  std::size_t piece(double r, int side) const;
  /// Piece k of a part (order 0) or of its first or second derivative (order 1, 2).
  const Polynomial& poly(LawPart part, std::size_t k, int order = 0) const;
  std::string name_;
  std::vector<double> breaks_;
  std::vector<Polynomial> j1_, j2_, j_;
  /// The derivatives of the pieces, by part (indexed by LawPart) and piece.
  std::array<std::vector<Polynomial>, 3> first_, second_;
  double alpha_ = 0.0;
};

/// The paper's law (4.7) with the DC split (4.8): alpha_j = 20.
std::shared_ptr<const ContactLaw> paper_law();
/// Linear springs: j = k r^2 / 2 for every r (k_nu = k r), convex.
std::shared_ptr<const ContactLaw> linear_law(double stiffness = 100.0);
/// A saw-tooth adhesive law: j' = k r on (0, r1], drops to `residual` at r1 (a concave kink
/// in j, so alpha_j = +inf), and stiffens again by k (r - r2) beyond r2.
std::shared_ptr<const ContactLaw> sawtooth_law(double stiffness = 100.0, double r1 = 0.01, double residual = 0.2,
                                               double r2 = 0.02);
/// A convex law with a kink: j = 0 for r <= 0 and sigma r + k r^2 / 2 for r > 0 (k_nu jumps
/// from 0 to sigma at r = 0).
std::shared_ptr<const ContactLaw> kinked_law(double sigma = 0.3, double stiffness = 100.0);
/// j = 0: pure Signorini contact.
std::shared_ptr<const ContactLaw> zero_law();

/// Tresca friction: j = g |r| for the tangential displacement r (convex, a kink at 0: the
/// friction force is g sign(r) when sliding and anything in [-g, g] when stuck).
std::shared_ptr<const ContactLaw> tresca_law(double bound = 0.1);
/// Slip-weakening friction: the friction bound falls linearly from g_static at r = 0 to
/// g_kinetic at |r| = slip and stays there (nonconvex: alpha_j = (g_static - g_kinetic) / slip).
std::shared_ptr<const ContactLaw> slip_weakening_law(double g_static = 0.1, double g_kinetic = 0.05,
                                                     double slip = 0.01);
/// The friction laws of [contact.friction]: tresca, slip-weakening, piecewise, coulomb (a Tresca
/// law whose bound is mu times the contact pressure: ContactProblem::friction_bound).
const std::vector<std::string>& friction_law_names();

/// The shipped laws by name: paper, linear, kinked, sawtooth, zero.
const std::vector<std::string>& contact_law_names();
/// A shipped law by name (case-insensitive); InputError listing the names otherwise.
std::shared_ptr<const ContactLaw> make_contact_law(std::string_view name);

}  // namespace hemivem
