#include <hemivem/error.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>

namespace hemivem {

namespace {

double eval(const Polynomial& p, double r) {
  double v = 0.0;
  for (auto it = p.rbegin(); it != p.rend(); ++it) v = v * r + *it;
  return v;
}

Polynomial differentiate(const Polynomial& p) {
  Polynomial d;
  for (std::size_t k = 1; k < p.size(); ++k) d.push_back(static_cast<double>(k) * p[k]);
  return d;
}

Polynomial subtract(const Polynomial& a, const Polynomial& b) {
  Polynomial c(std::max(a.size(), b.size()), 0.0);
  for (std::size_t k = 0; k < a.size(); ++k) c[k] += a[k];
  for (std::size_t k = 0; k < b.size(); ++k) c[k] -= b[k];
  return c;
}

std::string num(double x) {
  std::ostringstream s;
  s.precision(12);
  s << x;
  return s.str();
}

std::string part_name(LawPart p) { return p == LawPart::j ? "j" : (p == LawPart::j1 ? "j1" : "j2"); }

// Smallest value of the second derivative d2 = p'' on the interval (lo, hi) (may be +-inf):
// exact for p of degree <= 3, where p'' is linear.
double min_second_derivative(const Polynomial& d2, double lo, double hi) {
  if (d2.empty()) return 0.0;
  const double c0 = d2[0], c1 = d2.size() > 1 ? d2[1] : 0.0;
  auto at = [&](double r) {
    if (std::isinf(r)) return c1 == 0.0 ? c0 : (c1 * r > 0 ? std::numeric_limits<double>::infinity()
                                                            : -std::numeric_limits<double>::infinity());
    return c0 + c1 * r;
  };
  return std::min(at(lo), at(hi));
}

/// Finite, strictly increasing breakpoints; InputError naming the first that is not.
void check_breakpoints(const std::vector<double>& b, const std::string& where) {
  for (std::size_t k = 0; k < b.size(); ++k) {
    if (!std::isfinite(b[k])) throw InputError("breakpoint " + std::to_string(k) + " is not finite", where);
    if (k > 0 && !(b[k] > b[k - 1]))
      throw InputError("breakpoints must increase strictly: b" + std::to_string(k) + " = " + num(b[k]) + " after b" +
                           std::to_string(k - 1) + " = " + num(b[k - 1]),
                       where);
  }
}

/// Piece k of a part: degree <= 3, finite coefficients.
void check_piece(const Polynomial& p, const std::string& part, std::size_t k, const std::string& where) {
  if (p.size() > 4)
    throw InputError(part + " piece " + std::to_string(k) + " has degree " + std::to_string(p.size() - 1) +
                         "; pieces of degree <= 3 are supported",
                     where);
  for (double c : p)
    if (!std::isfinite(c)) throw InputError(part + " piece " + std::to_string(k) + " has a non-finite coefficient", where);
}

}  // namespace

PiecewisePolynomialLaw::PiecewisePolynomialLaw(std::string name, std::vector<double> breakpoints,
                                               std::vector<Polynomial> j1, std::vector<Polynomial> j2)
    : name_(std::move(name)), breaks_(std::move(breakpoints)), j1_(std::move(j1)), j2_(std::move(j2)) {
  const std::string where = "contact law '" + name_ + "'";
  const std::size_t m = breaks_.size() + 1;
  if (j1_.size() != m || j2_.size() != m)
    throw InputError(std::to_string(breaks_.size()) + " breakpoint(s) need " + std::to_string(m) +
                         " pieces for j1 and for j2; got " + std::to_string(j1_.size()) + " and " +
                         std::to_string(j2_.size()),
                     where);
  check_breakpoints(breaks_, where);
  for (LawPart part : {LawPart::j1, LawPart::j2})
    for (std::size_t k = 0; k < m; ++k) check_piece(poly(part, k), part_name(part), k, where);
  j_.resize(m);
  for (std::size_t k = 0; k < m; ++k) j_[k] = subtract(j1_[k], j2_[k]);
  for (LawPart part : {LawPart::j, LawPart::j1, LawPart::j2}) {
    const auto i = static_cast<std::size_t>(part);
    first_[i].resize(m);
    second_[i].resize(m);
    for (std::size_t k = 0; k < m; ++k) {
      first_[i][k] = differentiate(poly(part, k));
      second_[i][k] = differentiate(first_[i][k]);
    }
  }

  auto tol = [](double a, double b) { return 1e-10 * std::max({1.0, std::abs(a), std::abs(b)}); };
  for (LawPart part : {LawPart::j1, LawPart::j2}) {
    for (std::size_t k = 0; k < m; ++k) {
      const double lo = k == 0 ? -std::numeric_limits<double>::infinity() : breaks_[k - 1];
      const double hi = k + 1 == m ? std::numeric_limits<double>::infinity() : breaks_[k];
      const double c = min_second_derivative(poly(part, k, 2), lo, hi);
      if (c < -1e-12)
        throw InputError(part_name(part) + " is not convex on piece " + std::to_string(k) + " (" + num(lo) + ", " +
                             num(hi) + "]: its second derivative reaches " + num(c),
                         where);
    }
    for (std::size_t k = 0; k < breaks_.size(); ++k) {
      const double b = breaks_[k];
      const double left = eval(poly(part, k), b), right = eval(poly(part, k + 1), b);
      if (std::abs(left - right) > tol(left, right))
        throw InputError(part_name(part) + " is not continuous at breakpoint " + std::to_string(k) + " (r = " + num(b) +
                             "): " + num(left) + " on the left, " + num(right) + " on the right",
                         where);
      const double dl = eval(poly(part, k, 1), b), dr = eval(poly(part, k + 1, 1), b);
      if (dr < dl - tol(dl, dr))
        throw InputError(part_name(part) + " is not convex at breakpoint " + std::to_string(k) + " (r = " + num(b) +
                             "): its derivative drops from " + num(dl) + " to " + num(dr),
                         where);
    }
  }
  // alpha_j: the largest negative curvature of j on the pieces, +inf at a concave kink.
  for (std::size_t k = 0; k < m; ++k) {
    const double lo = k == 0 ? -std::numeric_limits<double>::infinity() : breaks_[k - 1];
    const double hi = k + 1 == m ? std::numeric_limits<double>::infinity() : breaks_[k];
    alpha_ = std::max(alpha_, -min_second_derivative(poly(LawPart::j, k, 2), lo, hi));
  }
  for (std::size_t k = 0; k < breaks_.size(); ++k) {
    const double dl = eval(poly(LawPart::j, k, 1), breaks_[k]), dr = eval(poly(LawPart::j, k + 1, 1), breaks_[k]);
    if (dr < dl - tol(dl, dr)) alpha_ = std::numeric_limits<double>::infinity();
  }
  if (alpha_ < 1e-12) alpha_ = 0.0;
}

PiecewisePolynomialLaw PiecewisePolynomialLaw::from_potential(std::string name, std::vector<double> breakpoints,
                                                              std::vector<Polynomial> j, std::vector<Polynomial> j1) {
  if (j.size() != j1.size())
    throw InputError("j has " + std::to_string(j.size()) + " pieces and j1 " + std::to_string(j1.size()),
                     "contact law '" + name + "'");
  std::vector<Polynomial> j2(j.size());
  for (std::size_t k = 0; k < j.size(); ++k) j2[k] = subtract(j1[k], j[k]);
  return PiecewisePolynomialLaw(std::move(name), std::move(breakpoints), std::move(j1), std::move(j2));
}

PiecewisePolynomialLaw PiecewisePolynomialLaw::from_j(std::string name, std::vector<double> breakpoints,
                                                     std::vector<Polynomial> j) {
  const std::string where = "contact law '" + name + "'";
  const std::size_t m = breakpoints.size() + 1;
  if (j.size() != m)
    throw InputError(std::to_string(breakpoints.size()) + " breakpoint(s) need " + std::to_string(m) +
                         " pieces for j; got " + std::to_string(j.size()),
                     where);
  for (std::size_t k = 0; k < m; ++k) check_piece(j[k], "j", k, where);
  check_breakpoints(breakpoints, where);
  auto tol = [](double a, double b) { return 1e-10 * std::max({1.0, std::abs(a), std::abs(b)}); };
  const double inf = std::numeric_limits<double>::infinity();
  // the curvature j2 needs on each piece, and the drops of j' at the breakpoints
  std::vector<double> curvature(m, 0.0), drop(breakpoints.size(), 0.0);
  for (std::size_t k = 0; k < m; ++k) {
    const double lo = k == 0 ? -inf : breakpoints[k - 1], hi = k + 1 == m ? inf : breakpoints[k];
    const double c = min_second_derivative(differentiate(differentiate(j[k])), lo, hi);
    if (std::isinf(c))
      throw InputError("j's curvature is unbounded below on piece " + std::to_string(k) + " (" + num(lo) + ", " +
                           num(hi) + "]: no split into convex parts exists",
                       where);
    curvature[k] = std::max(0.0, -c);
  }
  for (std::size_t k = 0; k < breakpoints.size(); ++k) {
    const double b = breakpoints[k];
    const double left = eval(j[k], b), right = eval(j[k + 1], b);
    if (std::abs(left - right) > tol(left, right))
      throw InputError("j is not continuous at breakpoint " + std::to_string(k) + " (r = " + num(b) + "): " + num(left) +
                           " on the left, " + num(right) + " on the right",
                       where);
    const double dl = eval(differentiate(j[k]), b), dr = eval(differentiate(j[k + 1]), b);
    if (dr < dl - tol(dl, dr)) drop[k] = dl - dr;
  }
  // j2 on piece k: v + s (r - x) + (curvature / 2) (r - x)^2 about the piece's left end x
  // (about b0 for piece 0), with j2(b0) = 0 and j2'(b0-) = 0.
  auto about = [](double v, double s, double c, double x) {
    return Polynomial{v - s * x + 0.5 * c * x * x, s - c * x, 0.5 * c};
  };
  std::vector<Polynomial> j2(m), j1(m);
  const double x0 = breakpoints.empty() ? 0.0 : breakpoints[0];
  j2[0] = about(0.0, 0.0, curvature[0], x0);
  double v = 0.0, slope = 0.0;
  for (std::size_t k = 1; k < m; ++k) {
    const double x = breakpoints[k - 1];
    if (k > 1) {
      const double h = x - breakpoints[k - 2];
      v += slope * h + 0.5 * curvature[k - 1] * h * h;
      slope += curvature[k - 1] * h;
    }
    slope += drop[k - 1];
    j2[k] = about(v, slope, curvature[k], x);
  }
  for (std::size_t k = 0; k < m; ++k) {
    j1[k] = subtract(j[k], Polynomial{});
    j1[k].resize(std::max(j[k].size(), j2[k].size()), 0.0);
    for (std::size_t i = 0; i < j2[k].size(); ++i) j1[k][i] += j2[k][i];
  }
  return PiecewisePolynomialLaw(std::move(name), std::move(breakpoints), std::move(j1), std::move(j2));
}

std::size_t PiecewisePolynomialLaw::piece(double r, int side) const {
  // piece k covers (b_{k-1}, b_k]; at a breakpoint the side decides.
  const auto it = side < 0 ? std::lower_bound(breaks_.begin(), breaks_.end(), r)
                           : std::upper_bound(breaks_.begin(), breaks_.end(), r);
  return static_cast<std::size_t>(it - breaks_.begin());
}

const Polynomial& PiecewisePolynomialLaw::poly(LawPart part, std::size_t k, int order) const {
  if (order == 1) return first_[static_cast<std::size_t>(part)][k];
  if (order == 2) return second_[static_cast<std::size_t>(part)][k];
  switch (part) {
    case LawPart::j:
      return j_[k];
    case LawPart::j1:
      return j1_[k];
    case LawPart::j2:
      return j2_[k];
  }
  throw InternalError("a LawPart out of range: " + std::to_string(static_cast<int>(part)));
}

double PiecewisePolynomialLaw::value(LawPart part, double r) const { return eval(poly(part, piece(r, -1)), r); }

double PiecewisePolynomialLaw::derivative(LawPart part, double r, int side) const {
  return eval(poly(part, piece(r, side), 1), r);
}

double PiecewisePolynomialLaw::second_derivative(LawPart part, double r, int side) const {
  return eval(poly(part, piece(r, side), 2), r);
}

std::vector<Polynomial> PiecewisePolynomialLaw::pieces(LawPart part) const {
  return part == LawPart::j1 ? j1_ : (part == LawPart::j2 ? j2_ : j_);
}

std::shared_ptr<const ContactLaw> paper_law() {
  // (4.7): j = 0 (r <= 0), 30 r^2 (0, 0.01], 0.8 r - 10 r^2 - 0.004 (0.01, 0.02), 30 r^2 - 0.8 r + 0.012
  // (4.8): j1 = 10 r^2, 40 r^2, 0.8 r - 0.004, 40 r^2 - 0.8 r + 0.012; hence j2 = 10 r^2.
  return std::make_shared<PiecewisePolynomialLaw>(PiecewisePolynomialLaw::from_potential(
      "paper", {0.0, 0.01, 0.02}, {{0.0}, {0.0, 0.0, 30.0}, {-0.004, 0.8, -10.0}, {0.012, -0.8, 30.0}},
      {{0.0, 0.0, 10.0}, {0.0, 0.0, 40.0}, {-0.004, 0.8}, {0.012, -0.8, 40.0}}));
}

std::shared_ptr<const ContactLaw> linear_law(double k) {
  if (!(k >= 0.0) || !std::isfinite(k)) throw InputError("stiffness " + num(k) + " must be finite and >= 0", "contact law 'linear'");
  return std::make_shared<PiecewisePolynomialLaw>("linear", std::vector<double>{},
                                                  std::vector<Polynomial>{{0.0, 0.0, 0.5 * k}},
                                                  std::vector<Polynomial>{{0.0}});
}

std::shared_ptr<const ContactLaw> sawtooth_law(double k, double r1, double residual, double r2) {
  const std::string where = "contact law 'sawtooth'";
  if (!(k > 0.0) || !(r1 > 0.0) || !(r2 > r1) || !(residual >= 0.0) || !(residual < k * r1))
    throw InputError("needs stiffness > 0, 0 < r1 < r2 and 0 <= residual < stiffness * r1, got stiffness " + num(k) +
                         ", r1 " + num(r1) + ", r2 " + num(r2) + ", residual " + num(residual),
                     where);
  // j = 0 (r <= 0); k r^2 / 2 on (0, r1]; k r1^2/2 + residual (r - r1) on (r1, r2];
  // then + k (r - r2)^2 / 2. j2 = (k r1 - residual) (r - r1)^+ absorbs the concave kink.
  const double drop = k * r1 - residual;
  const double c1 = 0.5 * k * r1 * r1;
  const Polynomial j_mid{c1 - residual * r1, residual};
  const Polynomial j_last{c1 - residual * r1 + 0.5 * k * r2 * r2, residual - k * r2, 0.5 * k};
  const Polynomial j2_after{-drop * r1, drop};
  std::vector<Polynomial> j{{0.0}, {0.0, 0.0, 0.5 * k}, j_mid, j_last};
  std::vector<Polynomial> j2{{0.0}, {0.0}, j2_after, j2_after};
  std::vector<Polynomial> j1(4);
  for (std::size_t i = 0; i < 4; ++i) {
    j1[i].assign(std::max(j[i].size(), j2[i].size()), 0.0);
    for (std::size_t c = 0; c < j[i].size(); ++c) j1[i][c] += j[i][c];
    for (std::size_t c = 0; c < j2[i].size(); ++c) j1[i][c] += j2[i][c];
  }
  return std::make_shared<PiecewisePolynomialLaw>("sawtooth", std::vector<double>{0.0, r1, r2}, j1, j2);
}

std::shared_ptr<const ContactLaw> kinked_law(double sigma, double k) {
  if (!(sigma >= 0.0) || !(k >= 0.0) || !std::isfinite(sigma) || !std::isfinite(k))
    throw InputError("needs finite sigma >= 0 and stiffness >= 0, got sigma " + num(sigma) + ", stiffness " + num(k),
                     "contact law 'kinked'");
  return std::make_shared<PiecewisePolynomialLaw>("kinked", std::vector<double>{0.0},
                                                  std::vector<Polynomial>{{0.0}, {0.0, sigma, 0.5 * k}},
                                                  std::vector<Polynomial>{{0.0}, {0.0}});
}

std::shared_ptr<const ContactLaw> zero_law() {
  return std::make_shared<PiecewisePolynomialLaw>("zero", std::vector<double>{}, std::vector<Polynomial>{{0.0}},
                                                  std::vector<Polynomial>{{0.0}});
}

std::shared_ptr<const ContactLaw> tresca_law(double bound) {
  if (!(bound >= 0.0) || !std::isfinite(bound))
    throw InputError("friction bound g " + num(bound) + " must be finite and >= 0", "friction law 'tresca'");
  // j = g |r|: convex, j1 = j, j2 = 0
  return std::make_shared<PiecewisePolynomialLaw>("tresca", std::vector<double>{0.0},
                                                  std::vector<Polynomial>{{0.0, -bound}, {0.0, bound}},
                                                  std::vector<Polynomial>{{0.0}, {0.0}});
}

std::shared_ptr<const ContactLaw> slip_weakening_law(double g_static, double g_kinetic, double slip) {
  const std::string where = "friction law 'slip-weakening'";
  if (!(g_static >= 0.0) || !std::isfinite(g_static) || !(g_kinetic >= 0.0) || !(g_kinetic <= g_static))
    throw InputError("needs finite bounds 0 <= kinetic <= static, got static " + num(g_static) + ", kinetic " +
                         num(g_kinetic),
                     where);
  if (!(slip > 0.0) || !std::isfinite(slip)) throw InputError("slip distance " + num(slip) + " must be finite and > 0", where);
  // |j'| falls linearly from g_s at r = 0 to g_k at |r| = delta, then stays:
  //   j = g_s |r| - (g_s - g_k) r^2 / (2 delta)      (|r| <= delta)
  //   j = g_k |r| + (g_s - g_k) delta / 2            (|r| >  delta)
  // j1 = g_s |r| (convex), j2 = j1 - j: (g_s - g_k) r^2 / (2 delta) inside, (g_s - g_k)(|r| - delta/2)
  // outside (convex: C1 at +-delta); alpha_j = (g_s - g_k) / delta.
  const double drop = g_static - g_kinetic, h = 0.5 * drop / slip;
  const std::vector<Polynomial> j1{{0.0, -g_static}, {0.0, -g_static}, {0.0, g_static}, {0.0, g_static}};
  const std::vector<Polynomial> j2{{-0.5 * drop * slip, -drop}, {0.0, 0.0, h}, {0.0, 0.0, h}, {-0.5 * drop * slip, drop}};
  return std::make_shared<PiecewisePolynomialLaw>("slip-weakening", std::vector<double>{-slip, 0.0, slip}, j1, j2);
}

const std::vector<std::string>& friction_law_names() {
  static const std::vector<std::string> names{"tresca", "slip-weakening", "piecewise", "coulomb"};
  return names;
}

const std::vector<std::string>& contact_law_names() {
  static const std::vector<std::string> names{"paper", "linear", "kinked", "sawtooth", "zero"};
  return names;
}

std::shared_ptr<const ContactLaw> make_contact_law(std::string_view name) {
  std::string s(name);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (s == "paper") return paper_law();
  if (s == "linear") return linear_law();
  if (s == "kinked") return kinked_law();
  if (s == "sawtooth") return sawtooth_law();
  if (s == "zero") return zero_law();
  std::string list;
  for (const auto& n : contact_law_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("unknown contact law '" + std::string(name) + "'; expected one of: " + list);
}

}  // namespace hemivem
