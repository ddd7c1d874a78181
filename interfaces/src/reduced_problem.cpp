#include <hemivem/error.hpp>
#include <hemivem/reduced_problem.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

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
  if (laws.size() != 1 || law_index.size() != size() || (law_index.size() > 0 && law_index.maxCoeff() != 0))
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

double ReducedProblem::energy(const Eigen::VectorXd& a) const {
  double f = 0.5 * a.dot(S * a) - c.dot(a);
  for (Eigen::Index i = 0; i < a.size(); ++i) f += w(i) * law_of(i).value(LawPart::j, a(i));
  return f;
}

Eigen::VectorXd ReducedProblem::subgradient_convex2(const Eigen::VectorXd& a) const {
  Eigen::VectorXd g2(a.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) g2(i) = w(i) * law_of(i).derivative(LawPart::j2, a(i), +1);
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
}

}  // namespace hemivem
