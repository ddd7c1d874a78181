// A smoothed contact law j_eps (docs/reference/engines.md, the smoothing): every breakpoint b where j' jumps (a kink) is
// rounded on [b - h, b + h], h = min(eps, a quarter of the distance to the neighbouring
// breakpoints), by the quintic Hermite interpolant of j, j', j'' at b -+ h. Hence j_eps is C^2
// across the window ends, C^1 everywhere (C^2 where it was), equal to j outside the windows,
// |j_eps - j| = O(h |jump of j'|) and |j_eps''| = O(|jump| / h) inside. Breakpoints where only
// j'' jumps are left alone unless round_curvature_jumps (j is C^1 there already). eps <= 0
// gives j itself (right derivatives at kinks). Works with any ContactLaw through its
// value / derivative(side) / second_derivative(side) / breakpoints API.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <hemivem/contact_law.hpp>

namespace hemivem::smoothing {

class SmoothedLaw {
 public:
  struct Window {
    double breakpoint = 0.0;
    double lo = 0.0, hi = 0.0;  ///< the window [b - h, b + h]
    bool kink = false;          ///< j' jumps at b (otherwise only j'')
    double a[6] = {0, 0, 0, 0, 0, 0};  ///< j_eps(lo + t (hi - lo)) = sum a_k t^k, t in [0, 1]
  };

  SmoothedLaw(std::shared_ptr<const ContactLaw> law, double epsilon, bool round_curvature_jumps = false)
      : law_(std::move(law)), epsilon_(epsilon) {
    const std::vector<double> b = law_->breakpoints();
    const std::vector<double> kinks = law_->kinks();  // the one definition of a kink (ContactLaw)
    for (std::size_t k = 0; k < b.size(); ++k) {
      const double sl = law_->second_derivative(LawPart::j, b[k], -1),
                   sr = law_->second_derivative(LawPart::j, b[k], +1);
      const bool kink = std::binary_search(kinks.begin(), kinks.end(), b[k]);
      const bool curv = std::abs(sr - sl) > ContactLaw::kink_tolerance * (std::abs(sl) + std::abs(sr));
      if (kink) ++kinks_;
      if (!(epsilon_ > 0.0) || !(kink || (curv && round_curvature_jumps))) continue;
      double h = epsilon_;
      if (k > 0) h = std::min(h, 0.25 * (b[k] - b[k - 1]));
      if (k + 1 < b.size()) h = std::min(h, 0.25 * (b[k + 1] - b[k]));
      Window w;
      w.breakpoint = b[k];
      w.lo = b[k] - h;
      w.hi = b[k] + h;
      w.kink = kink;
      const double L = w.hi - w.lo;
      const double f0 = law_->value(LawPart::j, w.lo), f1 = law_->value(LawPart::j, w.hi);
      const double d0 = law_->derivative(LawPart::j, w.lo, +1), d1 = law_->derivative(LawPart::j, w.hi, -1);
      const double s0 = law_->second_derivative(LawPart::j, w.lo, +1),
                   s1 = law_->second_derivative(LawPart::j, w.hi, -1);
      const double R0 = f1 - f0 - L * d0 - 0.5 * L * L * s0;
      const double R1 = L * (d1 - d0) - L * L * s0;
      const double R2 = L * L * (s1 - s0);
      w.a[0] = f0;
      w.a[1] = L * d0;
      w.a[2] = 0.5 * L * L * s0;
      w.a[3] = 10.0 * R0 - 4.0 * R1 + 0.5 * R2;
      w.a[4] = -15.0 * R0 + 7.0 * R1 - R2;
      w.a[5] = 6.0 * R0 - 3.0 * R1 + 0.5 * R2;
      windows_.push_back(w);
    }
    cuts_ = b;
    for (const Window& w : windows_) {
      cuts_.push_back(w.lo);
      cuts_.push_back(w.hi);
    }
    std::sort(cuts_.begin(), cuts_.end());
  }

  const ContactLaw& law() const noexcept { return *law_; }
  double epsilon() const noexcept { return epsilon_; }
  /// The rounded breakpoints.
  const std::vector<Window>& windows() const noexcept { return windows_; }
  /// Number of breakpoints where j' jumps (smoothing changes the problem only if > 0).
  int kinks() const noexcept { return kinks_; }

  double value(double r) const {
    if (const Window* w = find(r)) {
      const double t = (r - w->lo) / (w->hi - w->lo);
      const double* a = w->a;
      return a[0] + t * (a[1] + t * (a[2] + t * (a[3] + t * (a[4] + t * a[5]))));
    }
    return law_->value(LawPart::j, r);
  }
  double derivative(double r) const {
    if (const Window* w = find(r)) {
      const double L = w->hi - w->lo, t = (r - w->lo) / L;
      const double* a = w->a;
      return (a[1] + t * (2 * a[2] + t * (3 * a[3] + t * (4 * a[4] + t * 5 * a[5])))) / L;
    }
    return law_->derivative(LawPart::j, r, +1);
  }
  double second_derivative(double r) const {
    if (const Window* w = find(r)) {
      const double L = w->hi - w->lo, t = (r - w->lo) / L;
      const double* a = w->a;
      return (2 * a[2] + t * (6 * a[3] + t * (12 * a[4] + t * 20 * a[5]))) / (L * L);
    }
    return law_->second_derivative(LawPart::j, r, +1);
  }
  /// j_eps(y) - j_eps(x), without the cancellation of value(y) - value(x): the integral of
  /// j_eps' over [x, y] by 3-point Gauss-Legendre on each piece (exact for pieces of degree <= 5
  /// in j_eps, which covers laws of degree <= 3 and the quintic windows).
  double difference(double x, double y) const {
    if (x == y) return 0.0;
    if (y < x) return -difference(y, x);
    static const double node = std::sqrt(0.6), wm = 8.0 / 9.0, we = 5.0 / 9.0;
    double sum = 0.0;
    auto integrate = [&](double a, double b) {
      const double m = 0.5 * (a + b), h = 0.5 * (b - a);
      if (h <= 0.0) return;
      sum += h * (wm * piece_derivative(m, m) + we * piece_derivative(m - h * node, m) + we * piece_derivative(m + h * node, m));
    };
    double from = x;
    for (auto it = std::upper_bound(cuts_.begin(), cuts_.end(), x); it != cuts_.end() && *it < y; ++it) {
      integrate(from, *it);
      from = *it;
    }
    integrate(from, y);
    return sum;
  }

 private:
  // j_eps'(r) on the piece containing `mid` (r and mid in the same piece)
  double piece_derivative(double r, double mid) const {
    if (const Window* w = find(mid)) {
      const double L = w->hi - w->lo, t = (r - w->lo) / L;
      const double* a = w->a;
      return (a[1] + t * (2 * a[2] + t * (3 * a[3] + t * (4 * a[4] + t * 5 * a[5])))) / L;
    }
    return law_->derivative(LawPart::j, r, r < mid ? +1 : -1);
  }
  const Window* find(double r) const {
    for (const Window& w : windows_)
      if (r > w.lo && r < w.hi) return &w;
    return nullptr;
  }
  std::shared_ptr<const ContactLaw> law_;
  double epsilon_ = 0.0;
  std::vector<double> cuts_;  ///< the breakpoints and window ends, sorted: where j_eps' may change piece
  int kinks_ = 0;
  std::vector<Window> windows_;
};

/// The law r -> j(|r|) of a group's norm (ReducedProblem::groups): j on r >= 0 extended evenly
/// to r < 0, every part. For an even law it is the law itself; for any other law rising from
/// 0 it is even, so its smoothing (SmoothedLaw) is even too: the smoothed j_eps has j_eps'(0) = 0
/// and j_eps(|v|) is C^1 in the pair v, with a kink of the extension at 0 exactly where
/// j'(0+) > 0 (the cone point of w j(|v|)).
class EvenExtension final : public ContactLaw {
 public:
  explicit EvenExtension(std::shared_ptr<const ContactLaw> law) : law_(std::move(law)) {}
  std::string name() const override { return law_->name(); }
  double value(LawPart part, double r) const override { return law_->value(part, std::abs(r)); }
  double derivative(LawPart part, double r, int side) const override {
    if (r > 0.0) return law_->derivative(part, r, side);
    if (r < 0.0) return -law_->derivative(part, -r, -side);
    const double right = law_->derivative(part, 0.0, +1);
    return side > 0 ? right : -right;
  }
  double second_derivative(LawPart part, double r, int side) const override {
    if (r > 0.0) return law_->second_derivative(part, r, side);
    if (r < 0.0) return law_->second_derivative(part, -r, -side);
    return law_->second_derivative(part, 0.0, +1);
  }
  /// The positive breakpoints of the law, their mirror images and 0.
  std::vector<double> breakpoints() const override {
    std::vector<double> positive;
    for (double b : law_->breakpoints())
      if (b > 0.0) positive.push_back(b);
    std::vector<double> b;
    for (auto it = positive.rbegin(); it != positive.rend(); ++it) b.push_back(-*it);
    b.push_back(0.0);
    b.insert(b.end(), positive.begin(), positive.end());
    return b;
  }
  /// The law's bound (the extension's curvature on r > 0 is the law's; its kink at 0 is convex).
  double alpha() const override { return law_->alpha(); }
  using ContactLaw::value;

 private:
  std::shared_ptr<const ContactLaw> law_;
};

}  // namespace hemivem::smoothing
