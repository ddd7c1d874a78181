#include <hemivem/existence.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/minimizer_run.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>

namespace hemivem {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string num(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

/// The points a coordinate of law `law` is moved to or started at: its law's breakpoints and
/// the middles of the bounded pieces between them, inside [lo, hi], and the finite bounds.
std::vector<double> landmarks(const ContactLaw& law, double lo, double hi) {
  std::vector<double> v;
  const std::vector<double> b = law.breakpoints();
  for (std::size_t k = 0; k < b.size(); ++k) {
    v.push_back(b[k]);
    if (k + 1 < b.size()) v.push_back(0.5 * (b[k] + b[k + 1]));
  }
  if (std::isfinite(lo)) v.push_back(lo);
  if (std::isfinite(hi)) v.push_back(hi);
  std::vector<double> in;
  for (double x : v)
    if (x >= lo && x <= hi) in.push_back(x);
  std::sort(in.begin(), in.end());
  in.erase(std::unique(in.begin(), in.end()), in.end());
  return in;
}

/// The radii a group of law `law` is moved to or started at (its "breakpoints": j acts on the
/// pair's norm): 0, the law's positive breakpoints and the middles of the pieces between them.
std::vector<double> radii(const ContactLaw& law) {
  std::vector<double> b{0.0};
  for (double x : law.breakpoints())
    if (x > 0.0) b.push_back(x);
  std::vector<double> v;
  for (std::size_t k = 0; k < b.size(); ++k) {
    v.push_back(b[k]);
    if (k + 1 < b.size()) v.push_back(0.5 * (b[k] + b[k + 1]));
  }
  return v;
}

/// The pair of group g in a.
Eigen::Vector2d pair_of(const Eigen::VectorXd& a, const CoordinateGroup& g) { return {a(g.first), a(g.second)}; }

/// A unit vector along `preferred`, else along `fallback`, else (1, 0).
Eigen::Vector2d direction(const Eigen::Vector2d& preferred, const Eigen::Vector2d& fallback) {
  if (preferred.norm() > 0.0) return preferred.normalized();
  if (fallback.norm() > 0.0) return fallback.normalized();
  return {1.0, 0.0};
}

/// One certified critical point with the result of the first run that reached it.
struct Found {
  CriticalPoint point;
  MinimizerResult result;
};

// ---- the starts of phase 1 ------------------------------------------------------------------

/// S^+ c: c's components along the eigenvectors of S above null_space_tolerance divided by
/// their eigenvalues (zero where S has no eigenvalue above round-off).
Eigen::VectorXd pseudo_inverse_solution(const Eigen::MatrixXd& S, const Eigen::VectorXd& c) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(c.size());
  if (eig.info() != Eigen::Success) return x;
  const double top = eig.eigenvalues().cwiseAbs().maxCoeff();
  for (Eigen::Index k = 0; k < c.size(); ++k) {
    const double lambda = eig.eigenvalues()(k);
    if (lambda > null_space_tolerance * top) x += eig.eigenvectors().col(k) * (eig.eigenvectors().col(k).dot(c) / lambda);
  }
  return x.allFinite() ? x : Eigen::VectorXd::Zero(c.size());
}

/// Adds `a` projected onto C as the start `name`, unless that point is a start already.
void add_start(const ReducedProblem& p, std::vector<SearchStart>& out, std::string name, const Eigen::VectorXd& a) {
  const Eigen::VectorXd x = p.project(a);
  for (const auto& s : out)
    if (s.a == x) return;
  out.push_back({std::move(name), x});
}

/// The minimizer of the quadratic part alone, S^{-1} c (zero where S cannot be factored). When
/// S is singular (a motion the supports leave free) the quadratic part has no minimizer or
/// infinitely many: then the least-norm minimizer of |S x - c| over the range of S, S^+ c.
Eigen::VectorXd quadratic_minimizer(const ReducedProblem& p) {
  const Eigen::Index n = p.size();
  Eigen::VectorXd quadratic = Eigen::VectorXd::Zero(n);
  if (n > 0) {
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(p.S);
    const Eigen::VectorXd D = ldlt.info() == Eigen::Success ? Eigen::VectorXd(ldlt.vectorD()) : Eigen::VectorXd::Zero(n);
    if (!(D.minCoeff() > 1e-8 * D.cwiseAbs().maxCoeff())) return pseudo_inverse_solution(p.S, p.c);
    const Eigen::VectorXd x = ldlt.solve(p.c);
    if (x.allFinite()) quadratic = x;
  }
  return quadratic;
}

/// The lower and the upper bounds (0 where a bound is infinite), each when one is finite.
void add_bound_starts(const ReducedProblem& p, std::vector<SearchStart>& out) {
  const Eigen::Index n = p.size();
  Eigen::VectorXd lower(n), upper(n);
  bool any_lower = false, any_upper = false;
  for (Eigen::Index i = 0; i < n; ++i) {
    lower(i) = std::isfinite(p.lower(i)) ? p.lower(i) : 0.0;
    upper(i) = std::isfinite(p.upper(i)) ? p.upper(i) : 0.0;
    any_lower = any_lower || std::isfinite(p.lower(i));
    any_upper = any_upper || std::isfinite(p.upper(i));
  }
  if (any_lower) add_start(p, out, "lower bounds", lower);
  if (any_upper) add_start(p, out, "upper bounds", upper);
}

/// The k-th breakpoint and the k-th middle of a piece of each coordinate's own law, for every
/// k (a coordinate whose law has fewer keeps its value in `quadratic`). A group's breakpoints
/// are radii (0 and its law's positive breakpoints, with the middles between them): the pair is
/// put at the k-th along the quadratic minimizer's pair (along c_G where that vanishes).
void add_breakpoint_starts(const ReducedProblem& p, const Eigen::VectorXd& quadratic, std::vector<SearchStart>& out) {
  const Eigen::Index n = p.size();
  const Eigen::VectorXi group_of = p.group_of();
  std::vector<std::vector<double>> points(static_cast<std::size_t>(p.num_laws())), middles(points.size());
  std::vector<std::vector<double>> radii_at(points.size()), radii_between(points.size());
  std::size_t most = 0;
  for (int k = 0; k < p.num_laws(); ++k) {
    const auto b = p.law_by_number(k).breakpoints();
    points[static_cast<std::size_t>(k)] = b;
    for (std::size_t q = 0; q + 1 < b.size(); ++q) middles[static_cast<std::size_t>(k)].push_back(0.5 * (b[q] + b[q + 1]));
    most = std::max(most, b.size());
  }
  for (const CoordinateGroup& g : p.groups) {
    const auto k = static_cast<std::size_t>(p.law_index(g.first));
    if (!radii_at[k].empty()) continue;
    const std::vector<double> r = radii(p.law_by_number(p.law_index(g.first)));  // points and middles in turn
    for (std::size_t q = 0; q < r.size(); ++q) (q % 2 == 0 ? radii_at[k] : radii_between[k]).push_back(r[q]);
    most = std::max(most, radii_at[k].size());
  }
  for (std::size_t q = 0; q < most; ++q) {
    for (const bool at_points : {true, false}) {
      const auto& list = at_points ? points : middles;
      Eigen::VectorXd a(n);
      bool any = false;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (group_of(i) >= 0) continue;
        const auto& own = list[static_cast<std::size_t>(p.law_index(i))];
        a(i) = q < own.size() ? own[q] : quadratic(i);
        any = any || q < own.size();
      }
      for (const CoordinateGroup& g : p.groups) {
        const auto& own = (at_points ? radii_at : radii_between)[static_cast<std::size_t>(p.law_index(g.first))];
        const Eigen::Vector2d v = pair_of(quadratic, g);
        const Eigen::Vector2d x = q < own.size() ? Eigen::Vector2d(own[q] * direction(v, pair_of(p.c, g))) : v;
        a(g.first) = x(0);
        a(g.second) = x(1);
        any = any || q < own.size();
      }
      if (!any) continue;
      if (p.num_laws() == 1 && q < list[0].size())
        add_start(p, out, (at_points ? "breakpoint " : "middle of piece ") + num(list[0][q]), a);
      else
        add_start(p, out, (at_points ? "breakpoint #" : "middle of piece #") + std::to_string(q), a);
    }
  }
}

/// `count` points drawn uniformly (std::mt19937_64 seeded by `seed`) in a box around the
/// bounds, the breakpoints and the quadratic minimizer; a group's pair in the disc around the
/// origin that holds its law's positive breakpoints and the quadratic minimizer's pair (with
/// the same pad), uniformly in area (two draws at its first coordinate).
void add_random_starts(const ReducedProblem& p, const Eigen::VectorXd& quadratic, int seed, int count,
                       std::vector<SearchStart>& out) {
  const Eigen::Index n = p.size();
  double scale = quadratic.size() ? quadratic.lpNorm<Eigen::Infinity>() : 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (double b : p.law_of(i).breakpoints()) scale = std::max(scale, std::abs(b));
    if (std::isfinite(p.lower(i))) scale = std::max(scale, std::abs(p.lower(i)));
    if (std::isfinite(p.upper(i))) scale = std::max(scale, std::abs(p.upper(i)));
  }
  if (!(scale > 0.0)) scale = 1.0;
  std::mt19937_64 engine(static_cast<std::uint64_t>(seed));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::VectorXi group_of = p.group_of();
  for (int r = 0; r < count; ++r) {
    Eigen::VectorXd a(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      if (group_of(i) >= 0) {
        const CoordinateGroup& g = p.groups[static_cast<std::size_t>(group_of(i))];
        if (i != g.first) continue;
        double M = pair_of(quadratic, g).norm();
        for (double b : p.law_of(i).breakpoints()) M = std::max(M, b);
        const double R = M + 0.5 * M + 0.1 * scale;
        const double radius = R * std::sqrt(unit(engine)), angle = 2.0 * std::numbers::pi * unit(engine);
        a(g.first) = radius * std::cos(angle);
        a(g.second) = radius * std::sin(angle);
        continue;
      }
      double m = std::min(0.0, quadratic(i)), M = std::max(0.0, quadratic(i));
      for (double b : p.law_of(i).breakpoints()) {
        m = std::min(m, b);
        M = std::max(M, b);
      }
      const double pad = 0.5 * (M - m) + 0.1 * scale;
      const double lo = std::max(p.lower(i), m - pad), hi = std::min(p.upper(i), M + pad);
      a(i) = lo + (hi - lo) * unit(engine);
    }
    add_start(p, out, "random " + std::to_string(r + 1), a);
  }
}

// ---- the moves of phase 2 -------------------------------------------------------------------

/// One coordinate moved to a landmark of its law, or one group's pair moved to a radius of its
/// law (to = (to, to_second) along a direction), and the change of F by that move alone.
struct Move {
  double change;
  Eigen::Index i;
  double to;
  Eigen::Index second = -1;  ///< the group's second coordinate (-1: a single coordinate)
  double to_second = 0.0;
  double radius = 0.0;       ///< the group's radius
};

/// The moves from x, most promising (smallest change of F) first; none to a landmark within
/// `near` of the coordinate (of the pair, in the largest component). A group's norm is moved,
/// not one coordinate: to 0 (stuck) and to each positive radius of radii() along its current
/// direction and along -(S x - c)_G, the direction the force pulls it.
std::vector<Move> moves_from(const ReducedProblem& p, const Eigen::VectorXd& x, double near) {
  const Eigen::VectorXd g = p.S * x - p.c;
  const Eigen::VectorXi group_of = p.group_of();
  std::vector<Move> candidates;
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    if (group_of(i) >= 0) continue;
    const ContactLaw& law = p.law_of(i);
    for (double v : landmarks(law, p.lower(i), p.upper(i))) {
      const double d = v - x(i);
      if (std::abs(d) <= near) continue;
      const double change =
          g(i) * d + 0.5 * p.S(i, i) * d * d + p.w(i) * (law.value(LawPart::j, v) - law.value(LawPart::j, x(i)));
      candidates.push_back({change, i, v});
    }
  }
  for (const CoordinateGroup& G : p.groups) {
    const ContactLaw& law = p.law_of(G.first);
    const Eigen::Vector2d v = pair_of(x, G), force = -pair_of(g, G);
    Eigen::Matrix2d SG;
    SG << p.S(G.first, G.first), p.S(G.first, G.second), p.S(G.second, G.first), p.S(G.second, G.second);
    std::vector<Eigen::Vector2d> directions;
    if (v.norm() > 0.0) directions.push_back(v.normalized());
    if (force.norm() > 0.0) directions.push_back(force.normalized());
    if (directions.empty()) directions.push_back({1.0, 0.0});
    std::vector<Eigen::Vector2d> targets;
    for (double radius : radii(law))
      for (const Eigen::Vector2d& e : directions) {
        const Eigen::Vector2d to = radius * e;
        if (std::any_of(targets.begin(), targets.end(), [&](const Eigen::Vector2d& t) { return t == to; })) continue;
        targets.push_back(to);
        const Eigen::Vector2d d = to - v;
        if (d.cwiseAbs().maxCoeff() <= near) continue;
        const double change = pair_of(g, G).dot(d) + 0.5 * d.dot(SG * d) +
                              p.w(G.first) * (law.value(LawPart::j, radius) - law.value(LawPart::j, v.norm()));
        candidates.push_back({change, G.first, to(0), G.second, to(1), radius});
      }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Move& a, const Move& b) { return a.change < b.change; });
  return candidates;
}

// ---- one search -----------------------------------------------------------------------------

using Engines = std::vector<std::shared_ptr<const NonsmoothMinimizer>>;

/// One search: its local runs, the distinct certified critical points they reached, the best
/// uncertified run, the counts and the history (one record per local run).
class Search {
 public:
  Search(MinimizerRun& run, const Engines& engines, const GlobalSearchOptions& options)
      : run_(run), p_(run.problem()), engines_(engines), options_(options), local_(run.options()) {
    local_.callback = nullptr;  // the search reports its runs, not their iterations
    local_.check_existence = false;  // minimize() decided it for the search
  }

  /// A problem with one critical point: one run of the first engine from the given start.
  std::string solve_once() {
    local_run(*engines_.front(), "given", run_.start());
    return "the uniqueness margin is positive: one critical point, solved once by " + engines_.front()->name();
  }

  /// Phase 1 (every engine from every start) up to half the budget, then phase 2, then the
  /// starts left and phase 2 again when they found a lower point, while the budget lasts.
  std::string explore(const std::vector<SearchStart>& starts) {
    multistart(starts, options_.max_starts - options_.max_starts / 2);
    descend();
    const Found* before = lowest();
    const double settled = before ? before->point.objective : std::numeric_limits<double>::infinity();
    multistart(starts, options_.max_starts);
    if (lowest() && lowest()->point.objective < settled) descend();
    std::ostringstream h;
    h << "global search: " << found_.size() << " certified critical point(s) from " << runs_ << " local run(s) ("
      << phase1_ << " of the " << starts.size() << " x " << engines_.size() << " (start, engine) pairs, " << moves_
      << " single-coordinate move(s), " << improvements_ << " lowering F)";
    if (!budget_left()) h << "; budget spent";
    return h.str();
  }

  /// The lowest certified point's run (else the best uncertified one) with every critical
  /// point found, lowest first, and the search's counts; `how` begins its message.
  MinimizerResult result(const std::string& how) {
    std::sort(found_.begin(), found_.end(),
              [](const Found& a, const Found& b) { return a.point.objective < b.point.objective; });
    MinimizerResult out = found_.empty() ? best_uncertified_ : found_.front().result;
    for (const auto& f : found_) out.critical_points.push_back(f.point);
    std::ostringstream msg;
    msg << how;
    if (!found_.empty() && p_.uniqueness_margin > 0.0)
      msg << "; F = " << num(found_.front().point.objective);
    else if (!found_.empty())
      msg << "; lowest F = " << num(found_.front().point.objective) << " (reached by "
          << found_.front().point.engines.front() << ")";
    else
      msg << "; no run reached a certified critical point: " << out.message;
    out.message = msg.str();
    out.iterations = iterations_;
    out.function_evaluations = functions_;
    out.subgradient_evaluations = subgradients_;
    out.history = std::move(history_);
    out.timings = {{"total", run_.seconds()}};
    out.may_be_nonunique = !(p_.uniqueness_margin > 0.0);
    return out;
  }

 private:
  bool budget_left() const { return runs_ < options_.max_starts && run_.seconds() < options_.time_budget; }

  const Found* lowest() const {
    const Found* b = nullptr;
    for (const auto& f : found_)
      if (!b || f.point.objective < b->point.objective) b = &f;
    return b;
  }

  /// One local run of `engine` from `start`: counted, kept, recorded and reported.
  MinimizerResult local_run(const NonsmoothMinimizer& engine, const std::string& start_name, const Eigen::VectorXd& start) {
    MinimizerResult r = engine.minimize(p_, start, local_);
    ++runs_;
    iterations_ += r.iterations;
    functions_ += r.function_evaluations;
    subgradients_ += r.subgradient_evaluations;
    keep(engine, r);
    const Found* b = lowest();
    history_.push_back({runs_, r.objective, r.certificate.primal, r.certificate.dual, count_at_bound(p_, r.a), run_.seconds()});
    if (options_.progress)
      options_.progress({runs_, options_.max_starts, engine.name(), start_name, r.converged(), r.objective,
                         b ? b->point.objective : std::numeric_limits<double>::quiet_NaN(),
                         static_cast<int>(found_.size()), run_.seconds()});
    return r;
  }

  /// A certified run joins the critical point it agrees with, or is a new one; an uncertified
  /// run replaces the best uncertified one when its certificate is smaller.
  void keep(const NonsmoothMinimizer& engine, const MinimizerResult& r) {
    if (r.converged()) {
      auto same = std::find_if(found_.begin(), found_.end(), [&](const Found& f) {
        const double l = std::max(r.certificate.length_scale, f.point.certificate.length_scale);
        return (f.point.a - r.a).lpNorm<Eigen::Infinity>() <= options_.agree * l;
      });
      if (same == found_.end()) {
        found_.push_back({CriticalPoint{r.a, r.objective, r.certificate, 1, {engine.name()}}, r});
      } else {
        ++same->point.starts;
        auto& e = same->point.engines;
        if (std::find(e.begin(), e.end(), engine.name()) == e.end()) e.push_back(engine.name());
      }
    } else if (best_uncertified_.a.size() == 0 || r.certificate.worst() < best_uncertified_.certificate.worst()) {
      best_uncertified_ = r;
    }
  }

  /// Phase 1: the (start, engine) pairs not yet run, in order, until `limit` runs in all.
  void multistart(const std::vector<SearchStart>& starts, int limit) {
    const std::size_t pairs = starts.size() * engines_.size();
    for (; next_ < pairs && runs_ < limit && budget_left(); ++next_, ++phase1_) {
      const SearchStart& s = starts[next_ / engines_.size()];
      local_run(*engines_[next_ % engines_.size()], s.name, s.a);
    }
  }

  /// Phase 2: the first engine from single-coordinate (or single-group) moves of the lowest
  /// point, most promising first; a lower certified point starts the moves again from it.
  void descend() {
    bool improved = true;
    while (improved && budget_left() && lowest()) {
      improved = false;
      const Eigen::VectorXd x = lowest()->point.a;
      const double fx = lowest()->point.objective;
      const double near = options_.agree * std::max(1e-300, lowest()->point.certificate.length_scale);
      for (const Move& m : moves_from(p_, x, near)) {
        if (!budget_left()) break;
        Eigen::VectorXd start = x;
        start(m.i) = m.to;
        std::string name = "move " + std::to_string(m.i) + " -> " + num(m.to);
        if (m.second >= 0) {
          start(m.second) = m.to_second;
          name = "move group (" + std::to_string(m.i) + ", " + std::to_string(m.second) + ") -> radius " + num(m.radius);
        }
        ++moves_;
        const MinimizerResult r = local_run(*engines_.front(), name, start);
        if (r.converged() && r.objective < fx - 1e-12 * std::max(1.0, std::abs(fx))) {
          improved = true;
          ++improvements_;
          break;
        }
      }
    }
  }

  MinimizerRun& run_;
  const ReducedProblem& p_;
  const Engines& engines_;
  const GlobalSearchOptions& options_;
  MinimizerOptions local_;
  std::vector<Found> found_;
  MinimizerResult best_uncertified_;
  int runs_ = 0, iterations_ = 0, functions_ = 0, subgradients_ = 0;
  std::vector<IterationRecord> history_;
  std::size_t next_ = 0;  // the next (start, engine) pair of phase 1
  int phase1_ = 0, moves_ = 0, improvements_ = 0;
};

}  // namespace

GlobalSearch::GlobalSearch(std::vector<std::shared_ptr<const NonsmoothMinimizer>> engines, GlobalSearchOptions options)
    : engines_(std::move(engines)), options_(std::move(options)) {
  if (engines_.empty()) throw InputError("needs at least one minimizer", "global search");
  for (const auto& e : engines_)
    if (!e) throw InputError("a minimizer of the list is null", "global search");
  require_valid(options_, "global search");
}

bool GlobalSearch::takes_groups() const noexcept {
  return std::all_of(engines_.begin(), engines_.end(), [](const auto& e) { return e->takes_groups(); });
}

std::string GlobalSearch::groups_refusal() const {
  std::string names;
  for (const std::string& e : engines_without_groups()) names += (names.empty() ? "" : ", ") + e;
  return "the global search does not take groups of coordinates (the law of a tangential displacement's norm: "
         "friction on a solid's surface) with the engine(s) " + names + ", which do not; choose engines that do";
}

std::vector<std::string> GlobalSearch::engines_without_groups() const {
  std::vector<std::string> n;
  for (const auto& e : engines_)
    if (!e->takes_groups()) n.push_back(e->name());
  return n;
}

std::vector<std::string> GlobalSearch::engine_names() const {
  std::vector<std::string> n;
  for (const auto& e : engines_) n.push_back(e->name());
  return n;
}

std::vector<SearchStart> GlobalSearch::starts(const ReducedProblem& p, const Eigen::VectorXd& given) const {
  const Eigen::Index n = p.size();
  std::vector<SearchStart> out;
  add_start(p, out, "given", given.size() == n ? given : Eigen::VectorXd::Zero(n));
  const Eigen::VectorXd quadratic = quadratic_minimizer(p);
  add_start(p, out, "quadratic minimizer", quadratic);
  add_bound_starts(p, out);
  add_breakpoint_starts(p, quadratic, out);
  add_random_starts(p, quadratic, options_.seed, options_.random_starts, out);
  return out;
}

MinimizerResult GlobalSearch::run(MinimizerRun& run) const {
  const ReducedProblem& p = run.problem();
  Search search(run, engines_, options_);
  const std::string how = p.uniqueness_margin > 0.0 ? search.solve_once() : search.explore(starts(p, run.start()));
  return search.result(how);
}

std::unique_ptr<GlobalSearch> make_global_search(std::unique_ptr<NonsmoothMinimizer> first, GlobalSearchOptions options,
                                                 const std::vector<std::string>& others) {
  if (!first) throw InputError("needs a first minimizer", "global search");
  std::vector<std::shared_ptr<const NonsmoothMinimizer>> engines;
  engines.push_back(std::move(first));
  for (const auto& name : others.empty() ? available_minimizers() : others) {
    auto engine = make_minimizer(name);
    const bool listed = std::any_of(engines.begin(), engines.end(), [&](const auto& e) { return e->name() == engine->name(); });
    if (!listed) engines.push_back(std::move(engine));
  }
  return std::make_unique<GlobalSearch>(std::move(engines), std::move(options));
}

std::unique_ptr<GlobalSearch> make_global_search(const std::string& first, const std::map<std::string, double>& parameters,
                                                 GlobalSearchOptions options, const std::vector<std::string>& others) {
  return make_global_search(make_minimizer(first, parameters), std::move(options), others);
}

}  // namespace hemivem
