#include <hemivem/certificate.hpp>
#include <hemivem/error.hpp>

#include <charconv>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hemivem {

namespace {

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

std::string tolerance_problem(double tol) {
  if (tol >= min_tolerance && tol <= max_tolerance) return {};
  return "must be in [" + shortest(min_tolerance) + ", " + shortest(max_tolerance) + "], got " + shortest(tol);
}

void check_tolerance(double tol, const std::string& what, const std::string& where) {
  if (const std::string why = tolerance_problem(tol); !why.empty()) throw InputError(what + ": " + why, where);
}

double balance(double r, Interval law, Interval reaction, double* zeta, double* lambda) {
  *zeta = law.nearest(-r);
  *lambda = reaction.nearest(-r - *zeta);
  return std::abs(r + *zeta + *lambda);
}

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// 1. The length scale l.
double length_scale(const ReducedProblem& p, const Eigen::VectorXd& a, const Eigen::VectorXd& stiffness,
                    const Eigen::VectorXd& load) {
  double ell = a.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    for (double b : {p.lower(i), p.upper(i)})
      if (std::isfinite(b)) ell = std::max(ell, std::abs(b));
    const double d = stiffness(i);
    ell = std::max(ell, d > 0.0 ? std::abs(load(i)) / d : (load(i) == 0.0 ? 0.0 : inf));
  }
  return ell;
}

// 2. Every single coordinate within `window` of a bound or a kink of its law put there; returns
// the largest distance from the bounds.
double snap_coordinates(const ReducedProblem& p, const std::vector<std::vector<double>>& kinks_of, double window,
                        const Eigen::VectorXi& group_of, Eigen::VectorXd& x) {
  double primal = 0.0;
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    if (group_of(i) >= 0) continue;
    const double lo = p.lower(i), hi = p.upper(i);
    double target = x(i), distance = inf;
    for (double b : {lo, hi}) {
      const double d = std::abs(x(i) - b);
      if (std::isfinite(b) && d <= window && d < distance) target = b, distance = d;
    }
    const std::vector<double>& kinks = kinks_of[static_cast<std::size_t>(p.law_index(i))];
    const auto k = std::lower_bound(kinks.begin(), kinks.end(), x(i));
    for (auto it : {k, k == kinks.begin() ? k : k - 1}) {
      if (it == kinks.end()) continue;
      const double d = std::abs(x(i) - *it);
      if (d <= window && d < distance && *it >= lo && *it <= hi) target = *it, distance = d;
    }
    x(i) = target;
    primal = std::max(primal, std::max(lo - x(i), x(i) - hi));
  }
  return primal;
}

// 2. Every group's norm within `window` of a kink of j(|v|) put there by scaling the pair, the
// origin included where j'(0+) > 0 (the cone point of the norm); returns each group's radius as
// snapped (the kink itself, which the scaled pair's norm may miss by an ulp).
std::vector<double> snap_groups(const ReducedProblem& p, const std::vector<std::vector<double>>& kinks_of,
                                double window, Eigen::VectorXd& x) {
  std::vector<double> radius(p.groups.size());
  for (std::size_t k = 0; k < p.groups.size(); ++k) {
    const CoordinateGroup& g = p.groups[k];
    const double r = group_norm(x, g);
    const ContactLaw& law = p.law_of(g.first);
    double target = r, distance = inf;
    if (law.derivative(LawPart::j, 0.0, +1) > 0.0 && r <= window) target = 0.0, distance = r;
    for (double kink : kinks_of[static_cast<std::size_t>(p.law_index(g.first))]) {
      const double d = std::abs(r - kink);
      if (kink > 0.0 && d <= window && d < distance) target = kink, distance = d;
    }
    radius[k] = target;
    if (target == r) continue;
    const double scale = target == 0.0 ? 0.0 : target / r;
    x(g.first) *= scale;
    x(g.second) *= scale;
  }
  return radius;
}

// 3. A group's law force: the point of w times the Clarke subdifferential of j(|v|) nearest to
// -res, on the ray of v at radius r > 0, in the disc of radius w j'(0+) at v = 0.
Eigen::Vector2d group_law_force(const ContactLaw& law, double w, const Eigen::Vector2d& v, double r,
                                const Eigen::Vector2d& res) {
  if (r > 0.0) {
    const Eigen::Vector2d e = v.normalized();
    const Interval dj = law.clarke(r);
    return Interval{w * dj.lo, w * dj.hi}.nearest(-res.dot(e)) * e;
  }
  const double rho = w * law.derivative(LawPart::j, 0.0, +1), m = res.norm();
  return m <= rho ? Eigen::Vector2d(-res) : Eigen::Vector2d(-res * (rho / m));
}

}  // namespace

CertifiedPoint certify(const ReducedProblem& p, const Eigen::VectorXd& a, double tol) {
  if (a.size() != p.size() || p.S.rows() != p.size() || p.S.cols() != p.size() || p.c.size() != p.size())
    return certify(p, a, tol, {}, {}, {});
  return certify(
      p, a, tol,
      [&p](const Eigen::VectorXd& x) {
        SmoothGradient g;
        const Eigen::VectorXd Sa = p.S * x;
        g.r = Sa - p.c;
        g.force_size = p.size() == 0 ? 0.0 : std::max(p.c.cwiseAbs().maxCoeff(), Sa.cwiseAbs().maxCoeff());
        return g;
      },
      p.S.diagonal(), p.c);
}

CertifiedPoint certify(const ReducedProblem& p, const Eigen::VectorXd& a, double tol,
                       const std::function<SmoothGradient(const Eigen::VectorXd&)>& gradient,
                       const Eigen::VectorXd& stiffness, const Eigen::VectorXd& load,
                       const RowDistribution* processes) {
  check_tolerance(tol, "tolerance");
  const OneProcessRows alone(0);
  const RowDistribution& all = processes ? *processes : alone;
  CertifiedPoint out;
  out.certificate.tolerance = tol;
  const Eigen::Index n = p.size();
  const bool unusable = a.size() != n || !a.allFinite() || (p.laws.empty() && (n > 0 || !processes)) || !gradient ||
                        stiffness.size() != n || load.size() != n;
  if (all.max(unusable ? 1.0 : 0.0) > 0.0) return out;
  out.a = a;
  out.law_force = Eigen::VectorXd::Zero(n);
  out.reaction = Eigen::VectorXd::Zero(n);
  if (all.sum(static_cast<double>(n)) == 0.0) {
    out.certificate.primal = out.certificate.dual = 0.0;
    out.certificate.length_scale = out.certificate.force_scale = 0.0;
    return out;
  }
  const double ell = all.max(n == 0 ? 0.0 : length_scale(p, a, stiffness, load));
  // 2. snapping onto bounds and kinks (of each coordinate's law), a group's norm onto its law's
  std::vector<std::vector<double>> kinks_of(static_cast<std::size_t>(p.num_laws()));
  for (int k = 0; k < p.num_laws(); ++k) kinks_of[static_cast<std::size_t>(k)] = p.law_by_number(k).kinks();
  const double window = tol * ell;
  Eigen::VectorXd& x = out.a;
  const Eigen::VectorXi group_of = p.group_of();
  const double primal = all.max(snap_coordinates(p, kinks_of, window, group_of, x));
  const std::vector<double> radius = snap_groups(p, kinks_of, window, x);
  // 3. forces
  const SmoothGradient grad = gradient(x);
  if (all.max(grad.r.size() != n ? 1.0 : 0.0) > 0.0) return out;
  const Eigen::VectorXd& res = grad.r;
  double worst = std::isnan(grad.other) ? inf : grad.other, zeta_max = 0.0;
  for (std::size_t k = 0; k < p.groups.size(); ++k) {
    const CoordinateGroup& g = p.groups[k];
    const Eigen::Vector2d rg(res(g.first), res(g.second));
    const Eigen::Vector2d zeta =
        group_law_force(p.law_of(g.first), p.w(g.first), Eigen::Vector2d(x(g.first), x(g.second)), radius[k], rg);
    out.law_force(g.first) = zeta(0);
    out.law_force(g.second) = zeta(1);
    worst = std::max(worst, (rg + zeta).norm());
    zeta_max = std::max(zeta_max, zeta.cwiseAbs().maxCoeff());
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (group_of(i) >= 0) continue;
    const double lo = p.lower(i), hi = p.upper(i);
    const Interval dj = p.law_of(i).clarke(x(i));
    const Interval law{p.w(i) * dj.lo, p.w(i) * dj.hi};
    const Interval reaction{x(i) == lo ? -inf : 0.0, x(i) == hi ? inf : 0.0};
    worst = std::max(worst, balance(res(i), law, reaction, &out.law_force(i), &out.reaction(i)));
    zeta_max = std::max(zeta_max, std::abs(out.law_force(i)));
  }
  worst = all.max(worst);
  const double f = all.max(std::max({grad.force_size, zeta_max, force_floor}));
  // 4. the residuals (exactly zero stays zero, also where a scale vanishes)
  Certificate& c = out.certificate;
  c.length_scale = ell;
  c.force_scale = f;
  c.primal = primal <= 0.0 ? 0.0 : primal / ell;
  c.dual = worst == 0.0 ? 0.0 : worst / f;
  if (std::isnan(c.primal)) c.primal = inf;
  if (std::isnan(c.dual)) c.dual = inf;
  return out;
}

Certificate certificate(const ReducedProblem& p, const Eigen::VectorXd& a, double tol) {
  return certify(p, a, tol).certificate;
}

}  // namespace hemivem
