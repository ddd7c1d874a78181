#include <hemivem/error.hpp>
#include <hemivem/existence.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace hemivem {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A Cholesky pivot below this fraction of max S_ii sends the test to the eigenvalues.
constexpr double definite_pivot = 1e-8;
/// Entries of a direction (scaled to ||d||_inf = 1) below this are zero (round-off).
constexpr double zero_entry = 1e-9;
/// |phi| below this fraction of the size of its terms is zero.
constexpr double zero_rate = 1e-9;

/// The asymptotic cost of moving each coordinate: per unit to the right and to the left.
struct Rates {
  std::vector<double> right, left;
};

Rates rates_of(const ReducedProblem& p) {
  Rates r;
  for (int k = 0; k < p.num_laws(); ++k) {
    r.right.push_back(asymptotic_slope(p.law_by_number(k), +1));
    r.left.push_back(-asymptotic_slope(p.law_by_number(k), -1));
  }
  return r;
}

/// phi(d) / (sum of the sizes of its terms) for the null direction d = B y scaled to
/// ||d||_inf = 1 (d returned); NaN when the bounds forbid d.
double relative_rate(const ReducedProblem& p, const Rates& rates, const Eigen::MatrixXd& B, const Eigen::VectorXd& y,
                     Eigen::VectorXd& d, double* phi) {
  d = B * y;
  const double top = d.cwiseAbs().maxCoeff();
  if (!(top > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  d /= top;
  double sum = 0.0, size = 0.0;
  bool plus_inf = false, minus_inf = false;
  auto add_law = [&](double h) {
    plus_inf = plus_inf || h == kInf;
    minus_inf = minus_inf || h == -kInf;
    if (std::isfinite(h)) sum += h, size += std::abs(h);
  };
  const Eigen::VectorXi group_of = p.group_of();
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    if (std::abs(d(i)) <= zero_entry) {
      d(i) = 0.0;
      continue;
    }
    const bool right = d(i) > 0.0;
    if (right ? std::isfinite(p.upper(i)) : std::isfinite(p.lower(i))) return std::numeric_limits<double>::quiet_NaN();
    const auto k = static_cast<std::size_t>(p.law_index(i));
    if (group_of(i) < 0) add_law(p.w(i) * std::abs(d(i)) * (right ? rates.right[k] : rates.left[k]));
    sum -= p.c(i) * d(i);
    size += std::abs(p.c(i) * d(i));
  }
  // a group costs its law's rate at +inf times the length of its part of d
  for (const CoordinateGroup& g : p.groups)
    if (const double len = std::hypot(d(g.first), d(g.second)); len > 0.0)
      add_law(p.w(g.first) * len * rates.right[static_cast<std::size_t>(p.law_index(g.first))]);
  // a law growing faster than linearly stops the motion (even against one that falls so)
  if (plus_inf) return *phi = kInf;
  if (minus_inf) return *phi = -kInf;
  *phi = sum;
  return sum == 0.0 ? 0.0 : sum / size;
}

/// The normals of the hyperplanes on which phi(B y) changes its formula (the rows of B, each
/// direction once) and the coordinate hyperplanes of y.
std::vector<Eigen::VectorXd> hyperplanes(const Eigen::MatrixXd& B) {
  const Eigen::Index k = B.cols();
  const double top = B.rowwise().norm().maxCoeff();
  std::vector<Eigen::VectorXd> h;
  for (Eigen::Index i = 0; i < B.rows(); ++i) {
    Eigen::VectorXd r = B.row(i).transpose();
    const double norm = r.norm();
    if (!(norm > zero_entry * top)) continue;
    r /= norm;
    Eigen::Index lead = 0;
    r.cwiseAbs().maxCoeff(&lead);
    if (r(lead) < 0.0) r = -r;
    h.push_back(r);
  }
  for (Eigen::Index j = 0; j < k; ++j) h.push_back(Eigen::VectorXd::Unit(k, j));
  std::sort(h.begin(), h.end(), [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return std::lexicographical_compare(a.data(), a.data() + a.size(), b.data(), b.data() + b.size());
  });
  auto same = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).cwiseAbs().maxCoeff() <= 1e-12; };
  h.erase(std::unique(h.begin(), h.end(), same), h.end());
  return h;
}

/// The directions y to try: the extreme rays of the cells on which phi(B y) is linear (exact
/// for k <= 3), or the coordinate directions and the rows for a larger null space.
std::vector<Eigen::VectorXd> rays(const Eigen::MatrixXd& B) {
  const Eigen::Index k = B.cols();
  std::vector<Eigen::VectorXd> out;
  const std::vector<Eigen::VectorXd> h = hyperplanes(B);
  if (k == 1) {
    out.push_back(Eigen::VectorXd::Constant(1, 1.0));
  } else if (k == 2) {
    for (const auto& n : h) out.push_back(Eigen::Vector2d(-n(1), n(0)));
  } else if (k == 3) {
    for (std::size_t a = 0; a < h.size(); ++a)
      for (std::size_t b = a + 1; b < h.size(); ++b) {
        const Eigen::Vector3d x = Eigen::Vector3d(h[a]).cross(Eigen::Vector3d(h[b]));
        if (x.norm() > 1e-9) out.push_back(x.normalized());
      }
  } else {
    out = h;
  }
  const std::size_t m = out.size();
  for (std::size_t j = 0; j < m; ++j) out.push_back(-out[j]);
  return out;
}

std::string unbounded_message(const Existence& e) {
  Eigen::Index at = 0;
  e.direction.cwiseAbs().maxCoeff(&at);
  std::ostringstream s;
  s.precision(6);
  s << "the energy is unbounded below along a motion the supports leave free (a null direction of S, "
    << e.null_dimension << "-dimensional; largest at coordinate " << at << "), on which F falls at the rate "
    << e.slope << " per unit of motion: the load pushes the body away from its support; there is no solution";
  return s.str();
}

}  // namespace

double asymptotic_slope(const ContactLaw& law, int side) {
  const double s = side > 0 ? 1.0 : -1.0;
  const std::vector<double> b = law.breakpoints();
  double reach = 1.0;
  for (double x : b) reach = std::max(reach, std::abs(x));
  const double outer = b.empty() ? 0.0 : (side > 0 ? b.back() : b.front());
  const double r1 = outer + s * reach, r2 = outer + 2.0 * s * reach;
  const double d1 = law.derivative(LawPart::j, r1, +1);
  const double k1 = law.second_derivative(LawPart::j, r1, +1), k2 = law.second_derivative(LawPart::j, r2, +1);
  const double noise = 1e-12 * (std::abs(k1) + std::abs(k2) + std::abs(d1) / reach);
  // beyond the outermost breakpoint j'' is affine (a piece of degree <= 3): its sign far away
  double far = 0.0;
  if (std::abs(k2 - k1) > noise) far = k2 > k1 ? 1.0 : -1.0;
  else if (std::abs(k1) > noise) far = k1 > 0.0 ? 1.0 : -1.0;
  return far == 0.0 ? d1 : s * far * kInf;
}

Eigen::MatrixXd null_space(const Eigen::MatrixXd& S, double relative_tolerance) {
  const Eigen::Index n = S.rows();
  if (S.cols() != n) throw InputError("null_space: S is " + std::to_string(n) + "x" + std::to_string(S.cols()) + ", expected a square matrix");
  if (n == 0) return Eigen::MatrixXd(0, 0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  if (eig.info() != Eigen::Success) throw NumericalError("the eigenvalues of S could not be computed");
  const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
  const double top = lambda.cwiseAbs().maxCoeff();
  Eigen::Index k = 0;
  while (k < n && lambda(k) <= relative_tolerance * top) ++k;
  return eig.eigenvectors().leftCols(k);
}

Existence check_existence(const ReducedProblem& p, const Eigen::MatrixXd& null_basis) {
  if (null_basis.rows() != p.size())
    throw InputError("the null space basis has " + std::to_string(null_basis.rows()) + " rows, the problem " +
                     std::to_string(p.size()) + " coordinates");
  Existence e;
  e.null_dimension = static_cast<int>(null_basis.cols());
  if (e.null_dimension == 0) return e;
  const Rates r = rates_of(p);
  double lowest = kInf, lowest_phi = kInf;
  Eigen::VectorXd d, worst;
  std::vector<Eigen::VectorXd> candidates = rays(null_basis);
  if (!p.groups.empty()) {
    // a group's term is smallest against the load: the null part of c, whole and per group
    candidates.push_back(null_basis.transpose() * p.c);
    for (const CoordinateGroup& g : p.groups) {
      Eigen::VectorXd cg = Eigen::VectorXd::Zero(p.size());
      cg(g.first) = p.c(g.first);
      cg(g.second) = p.c(g.second);
      candidates.push_back(null_basis.transpose() * cg);
    }
  }
  for (const Eigen::VectorXd& y : candidates) {
    double phi = kInf;
    const double rel = relative_rate(p, r, null_basis, y, d, &phi);
    if (std::isnan(rel) || !(rel < lowest)) continue;
    lowest = rel;
    lowest_phi = phi;
    worst = d;
    if (rel == -kInf) break;
  }
  e.coercive = lowest > zero_rate;
  if (lowest < -zero_rate) {
    e.bounded = false;
    e.direction = worst;
    e.slope = lowest_phi;
    e.message = unbounded_message(e);
  } else {
    e.slope = std::numeric_limits<double>::quiet_NaN();
  }
  return e;
}

Existence check_existence(const ReducedProblem& p) {
  if (p.size() == 0) return {};
  const Eigen::LLT<Eigen::MatrixXd> llt(p.S);
  if (llt.info() == Eigen::Success) {
    const double top = p.S.diagonal().cwiseAbs().maxCoeff();
    if (llt.matrixLLT().diagonal().cwiseAbs2().minCoeff() > definite_pivot * top)
      return check_existence(p, Eigen::MatrixXd(p.size(), 0));
  }
  return check_existence(p, null_space(p.S));
}

}  // namespace hemivem
