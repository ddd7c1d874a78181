#include <hemivem/error.hpp>
#include <hemivem/reduced_problem.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <vector>

namespace hemivem {

std::string to_string(ConstraintKind kind) {
  switch (kind) {
    case ConstraintKind::none: return "none";
    case ConstraintKind::one_sided: return "one-sided";
    case ConstraintKind::box: return "box";
    case ConstraintKind::bilateral: return "bilateral";
  }
  throw InternalError("a ConstraintKind out of range: " + std::to_string(static_cast<int>(kind)));
}

ConstraintKind constraint_kind_from_string(std::string_view name) {
  std::string s(name);
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (s == "none") return ConstraintKind::none;
  if (s == "one-sided" || s == "one_sided") return ConstraintKind::one_sided;
  if (s == "box") return ConstraintKind::box;
  if (s == "bilateral") return ConstraintKind::bilateral;
  throw InputError("unknown constraint '" + std::string(name) + "'; expected none, one-sided, box or bilateral");
}

ReducedProblem ReducedProblem::uniform(Eigen::MatrixXd S, Eigen::VectorXd c, Eigen::VectorXd w,
                                       std::shared_ptr<const ContactLaw> law, ConstraintKind constraint,
                                       const Eigen::VectorXd& g) {
  const Eigen::Index n = c.size();
  const bool gapped = constraint == ConstraintKind::one_sided || constraint == ConstraintKind::box;
  if (gapped && g.size() != n)
    throw InputError("inconsistent sizes in the reduced problem: c " + std::to_string(n) + ", g " +
                     std::to_string(g.size()) + " (the " + to_string(constraint) + " constraint needs one gap per coordinate)");
  ReducedProblem p;
  p.S = std::move(S);
  p.c = std::move(c);
  p.w = std::move(w);
  p.laws = {std::move(law)};
  p.law_index = Eigen::VectorXi::Zero(n);
  p.lo.resize(n);
  p.hi.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double gi = gapped ? g(i) : 0.0;
    p.lo(i) = lower_bound(constraint, gi);
    p.hi(i) = upper_bound(constraint, gi);
  }
  return p;
}

namespace {

/// True when every coordinate has the bounds of `kind` with the gap hi(i).
bool bounds_of(const ReducedProblem& p, ConstraintKind kind) {
  const Eigen::Index n = p.size();
  if (p.lo.size() != n || p.hi.size() != n) return false;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lo = p.lo(i), hi = p.hi(i);
    bool fits = false;
    switch (kind) {
      case ConstraintKind::none: fits = lo == lower_bound(kind, 0.0) && hi == upper_bound(kind, 0.0); break;
      case ConstraintKind::one_sided: fits = lo == lower_bound(kind, hi) && !std::isnan(hi); break;
      case ConstraintKind::bilateral: fits = lo == 0.0 && hi == 0.0 && !std::signbit(lo); break;
      case ConstraintKind::box: fits = hi >= 0.0 && std::isfinite(hi) && lo == lower_bound(kind, hi); break;
    }
    if (!fits) return false;
  }
  return true;
}

}  // namespace

std::optional<UniformForm> ReducedProblem::uniform_form() const {
  if (!groups.empty() || laws.size() != 1 || law_index.size() != size() || (law_index.size() > 0 && law_index.maxCoeff() != 0))
    return std::nullopt;
  // the first kind that fits: a problem without bounds is "none", not one-sided with infinite gaps
  for (ConstraintKind kind :
       {ConstraintKind::none, ConstraintKind::one_sided, ConstraintKind::bilateral, ConstraintKind::box}) {
    if (!bounds_of(*this, kind)) continue;
    const bool gapped = kind == ConstraintKind::one_sided || kind == ConstraintKind::box;
    return UniformForm{laws.front(), kind, gapped ? hi : Eigen::VectorXd::Zero(size())};
  }
  return std::nullopt;
}

bool ReducedProblem::all_laws_convex() const {
  return std::all_of(laws.begin(), laws.end(), [](const auto& law) { return law->is_convex(); });
}

Eigen::VectorXi ReducedProblem::group_of() const {
  Eigen::VectorXi of = Eigen::VectorXi::Constant(size(), -1);
  for (std::size_t k = 0; k < groups.size(); ++k) of(groups[k].first) = of(groups[k].second) = static_cast<int>(k);
  return of;
}

double ReducedProblem::energy(const Eigen::VectorXd& a) const { return law_energy(a, 0.5 * a.dot(S * a) - c.dot(a)); }

double ReducedProblem::law_energy(const Eigen::VectorXd& a, double onto) const {
  double f = onto;
  const Eigen::VectorXi of = group_of();
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (of(i) < 0) f += w(i) * law_of(i).value(LawPart::j, a(i));
  for (const CoordinateGroup& g : groups) f += w(g.first) * law_of(g.first).value(LawPart::j, group_norm(a, g));
  return f;
}

Eigen::VectorXd ReducedProblem::subgradient_convex2(const Eigen::VectorXd& a) const {
  Eigen::VectorXd g2(a.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) g2(i) = w(i) * law_of(i).derivative(LawPart::j2, a(i), +1);
  for (const CoordinateGroup& g : groups) {
    const double r = group_norm(a, g);
    const double s = r > 0.0 ? w(g.first) * law_of(g.first).derivative(LawPart::j2, r, +1) / r : 0.0;
    g2(g.first) = s * a(g.first);
    g2(g.second) = s * a(g.second);
  }
  return g2;
}

Eigen::VectorXd ReducedProblem::project(const Eigen::VectorXd& a) const {
  Eigen::VectorXd p(a.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) p(i) = std::min(std::max(a(i), lower(i)), upper(i));
  return p;
}

Eigen::VectorXd ReducedProblem::alphas() const {
  Eigen::VectorXd alpha(size());
  for (Eigen::Index i = 0; i < size(); ++i) alpha(i) = law_of(i).alpha();
  return alpha;
}

void check_sizes(const ReducedProblem& p, const std::string& where) {
  const Eigen::Index n = p.size();
  if (p.laws.empty()) throw InputError("the reduced problem has no contact law", where);
  for (const auto& l : p.laws)
    if (!l) throw InputError("the reduced problem has a null law in its list of laws", where);
  if (p.S.rows() != n || p.S.cols() != n || p.w.size() != n || p.law_index.size() != n || p.lo.size() != n ||
      p.hi.size() != n)
    throw InputError("inconsistent sizes in the reduced problem: S " + std::to_string(p.S.rows()) + "x" +
                         std::to_string(p.S.cols()) + ", c " + std::to_string(n) + ", w " + std::to_string(p.w.size()) +
                         ", law_index " + std::to_string(p.law_index.size()) + ", lower bounds " +
                         std::to_string(p.lo.size()) + ", upper bounds " + std::to_string(p.hi.size()),
                     where);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (p.law_index(i) < 0 || p.law_index(i) >= static_cast<int>(p.laws.size()))
      throw InputError("coordinate " + std::to_string(i) + " has law index " + std::to_string(p.law_index(i)) +
                           ", expected 0.." + std::to_string(p.laws.size() - 1),
                       where);
    if (!(p.lo(i) <= p.hi(i)))
      throw InputError("coordinate " + std::to_string(i) + " has bounds [" + std::to_string(p.lo(i)) + ", " +
                           std::to_string(p.hi(i)) + "]; expected lower <= upper",
                       where);
  }
  std::vector<char> grouped(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < p.groups.size(); ++k) {
    const CoordinateGroup& g = p.groups[k];
    const std::string name = "group " + std::to_string(k) + " (coordinates " + std::to_string(g.first) + " and " +
                             std::to_string(g.second) + ")";
    if (g.first < 0 || g.first >= n || g.second < 0 || g.second >= n || g.first == g.second)
      throw InputError(name + ": expected two distinct coordinates in 0.." + std::to_string(n - 1), where);
    for (Eigen::Index i : {g.first, g.second}) {
      if (grouped[static_cast<std::size_t>(i)]) throw InputError(name + ": coordinate " + std::to_string(i) + " is in another group", where);
      grouped[static_cast<std::size_t>(i)] = 1;
      if (std::isfinite(p.lo(i)) || std::isfinite(p.hi(i)))
        throw InputError(name + ": coordinate " + std::to_string(i) + " has a bound; a group's coordinates have none", where);
    }
    if (p.law_index(g.first) != p.law_index(g.second) || p.w(g.first) != p.w(g.second))
      throw InputError(name + ": its coordinates differ in law or weight; a group has one of each", where);
    const ContactLaw& law = p.law_of(g.first);
    for (LawPart part : {LawPart::j, LawPart::j1, LawPart::j2})
      if (!(law.derivative(part, 0.0, +1) >= 0.0))
        throw InputError(name + ": its law '" + law.name() + "' falls from 0 (" + to_string(part) + "'(0+) = " +
                             std::to_string(law.derivative(part, 0.0, +1)) +
                             "); a law of a norm must rise from 0, as every even law does",
                         where);
  }
}

}  // namespace hemivem
