// The contract of a normal-compliance contact law (docs/reference/scenes.md, contact.law).
//
// A law is its potential j (locally Lipschitz, possibly nonconvex and nonsmooth) with a
// DC split j = j1 - j2, j1 and j2 convex. For every r it gives the values, the one-sided
// derivatives and, where it exists, the second derivative of each part; the Clarke
// subdifferential of j at r is the interval between the one-sided derivatives of j.
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace hemivem {

/// Which function of the law: the potential j or one of its convex parts j1, j2.
enum class LawPart { j, j1, j2 };
/// "j", "j1", "j2".
std::string to_string(LawPart part);
/// The names of to_string (case-insensitive); InputError otherwise.
LawPart law_part_from_string(std::string_view name);

/// A closed interval [lo, hi].
struct Interval {
  double lo = 0.0;
  double hi = 0.0;
  bool contains(double x) const noexcept { return lo <= x && x <= hi; }
  /// The point of the interval nearest to x.
  double nearest(double x) const noexcept { return x < lo ? lo : (x > hi ? hi : x); }
};

class ContactLaw {
 public:
  virtual ~ContactLaw() = default;

  virtual std::string name() const = 0;

  virtual double value(LawPart part, double r) const = 0;
  /// j'(r-) for side < 0, j'(r+) for side > 0 (of the given part).
  virtual double derivative(LawPart part, double r, int side) const = 0;
  /// The second derivative on the side given (it exists on each side for a
  /// piecewise-smooth law).
  virtual double second_derivative(LawPart part, double r, int side) const = 0;

  /// Points where some part is not twice differentiable (sorted).
  virtual std::vector<double> breakpoints() const = 0;

  /// The kinks of j: the breakpoints where j' jumps, |j'(b+) - j'(b-)| > kink_tolerance *
  /// (|j'(b-)| + |j'(b+)|) (sorted). The one definition every engine, the smoothing and the
  /// certificate use; a law that knows its kinks exactly may override it.
  virtual std::vector<double> kinks() const {
    std::vector<double> k;
    for (double b : breakpoints()) {
      const double l = derivative(LawPart::j, b, -1), r = derivative(LawPart::j, b, +1);
      if (std::abs(r - l) > kink_tolerance * (std::abs(l) + std::abs(r))) k.push_back(b);
    }
    return k;
  }
  /// Relative size of a jump of j' that makes a breakpoint a kink (smaller jumps are rounding
  /// in a law whose pieces join with a continuous derivative).
  static constexpr double kink_tolerance = 1e-12;

  /// The largest negative curvature of j: alpha_j >= 0 such that j + alpha_j r^2 / 2 is
  /// convex; +infinity when j has a concave kink (a downward jump of j').
  virtual double alpha() const = 0;

  /// True when j itself is convex (alpha() == 0): no DC loop is needed.
  bool is_convex() const { return alpha() == 0.0; }

  double value(double r) const { return value(LawPart::j, r); }
  /// Clarke subdifferential of j at r: the interval spanned by the one-sided derivatives.
  Interval clarke(double r) const {
    const double a = derivative(LawPart::j, r, -1), b = derivative(LawPart::j, r, +1);
    return a <= b ? Interval{a, b} : Interval{b, a};
  }
};

}  // namespace hemivem
