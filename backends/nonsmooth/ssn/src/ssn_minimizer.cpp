// The semismooth Newton / active-set engine: see ssn_minimizer.hpp and README.md.
#include <hemivem/ssn_minimizer.hpp>

#include <hemivem/error.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace hemivem {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Parameters {
  double armijo = 1e-4;
  double backtrack = 0.5;
  int max_backtracks = 30;
  double active_scale = 1.0;
  double shift = 1e-8;
};

Parameters read_parameters(const MinimizerOptions& o) {
  const std::string where = "minimizer 'ssn'";
  Parameters p;
  for (const auto& [name, v] : o.parameters) {
    if (name == "armijo") {
      if (!(v > 0.0 && v < 0.5)) throw InputError("armijo must be in (0, 1/2)", where);
      p.armijo = v;
    } else if (name == "backtrack") {
      if (!(v > 0.0 && v < 1.0)) throw InputError("backtrack must be in (0, 1)", where);
      p.backtrack = v;
    } else if (name == "max_backtracks") {
      if (!(v >= 1.0 && v <= 1000.0)) throw InputError("max_backtracks must be in [1, 1000]", where);
      p.max_backtracks = static_cast<int>(v);
    } else if (name == "active_scale") {
      if (!(v >= 0.0 && std::isfinite(v))) throw InputError("active_scale must be finite and >= 0", where);
      p.active_scale = v;
    } else if (name == "shift") {
      if (!(v > 0.0 && std::isfinite(v))) throw InputError("shift must be finite and > 0", where);
      p.shift = v;
    } else {
      throw InputError("unknown parameter '" + name + "'; ssn knows armijo, backtrack, max_backtracks, active_scale, shift",
                       where);
    }
  }
  return p;
}

/// What an iteration knows about one node.
struct NodeState {
  double lo = 0.0, hi = 0.0;  ///< its piece box (lo == hi: fixed)
  double grad = 0.0;          ///< one-sided derivative of F on the side of motion
  double hess = 0.0;          ///< S_ii + w_i j''(a_i, side)
  int side = 1;
};

class Solver {
 public:
  Solver(const ReducedProblem& p, const MinimizerOptions& o, const Parameters& prm)
      : p_(p), o_(o), prm_(prm), n_(p.size()) {
    for (double b : p.law->breakpoints()) {
      const double l = p.law->derivative(LawPart::j, b, -1), r = p.law->derivative(LawPart::j, b, +1);
      if (std::abs(r - l) > 1e-12 * std::max({1.0, std::abs(l), std::abs(r)})) kinks_.push_back(b);
    }
    std::sort(kinks_.begin(), kinks_.end());
    scale_ = std::max(p.c.size() ? p.c.cwiseAbs().maxCoeff() : 0.0, std::numeric_limits<double>::min());
  }

  MinimizerResult run(const Eigen::VectorXd& start) {
    const auto t0 = Clock::now();
    MinimizerResult r;
    Eigen::VectorXd a = p_.project(start.size() == 0 ? Eigen::VectorXd::Zero(n_) : start);
    double F = energy(a, &q_, r);
    double res = residual(a, q_, r);
    r.history.push_back({0, F, res, 0.0, count_at_bound(a), since(t0)});
    double t_factor = 0.0, t_search = 0.0;
    int fallbacks = 0, shifted = 0, stagnant = 0;
    double best_res = res;
    MinimizerStatus status = MinimizerStatus::converged;
    std::vector<NodeState> st(static_cast<std::size_t>(n_));
    Eigen::VectorXd d(n_), trial(n_), qt(n_);
    std::vector<Eigen::Index> fr, ea;
    while (true) {
      if (res <= o_.tolerance) break;
      if (r.iterations >= o_.max_iterations) { status = MinimizerStatus::iteration_limit; break; }
      if (evaluations(r) >= o_.max_evaluations) { status = MinimizerStatus::evaluation_limit; break; }
      // ---- classify: fixed at a knot, or moving inside a piece box
      classify(a, st);
      double eps = 0.0;
      for (Eigen::Index i = 0; i < n_; ++i) {
        const NodeState& s = st[static_cast<std::size_t>(i)];
        if (s.lo == s.hi) continue;
        eps = std::max(eps, std::abs(std::clamp(a(i) - s.grad / scaling(i, s), s.lo, s.hi) - a(i)));
      }
      eps *= prm_.active_scale;
      // ---- Newton direction on the free nodes, epsilon-active nodes sent to their knot
      fr.clear();
      ea.clear();
      d.setZero();
      for (Eigen::Index i = 0; i < n_; ++i) {
        const NodeState& s = st[static_cast<std::size_t>(i)];
        if (s.lo == s.hi) continue;
        if (s.grad > 0.0 && a(i) - s.lo <= eps) {
          d(i) = s.lo - a(i);
          ea.push_back(i);
        } else if (s.grad < 0.0 && s.hi - a(i) <= eps) {
          d(i) = s.hi - a(i);
          ea.push_back(i);
        } else {
          fr.push_back(i);
        }
      }
      bool newton = false;
      if (!fr.empty()) {
        const auto tf = Clock::now();
        Eigen::VectorXd rhs(static_cast<Eigen::Index>(fr.size()));
        for (std::size_t k = 0; k < fr.size(); ++k) rhs(static_cast<Eigen::Index>(k)) = -st[static_cast<std::size_t>(fr[k])].grad;
        if (!ea.empty()) rhs.noalias() -= p_.S(fr, ea) * d(ea);
        Eigen::MatrixXd H = p_.S(fr, fr);
        double min_diag = kInf, max_diag = 0.0;
        for (std::size_t k = 0; k < fr.size(); ++k) {
          const auto kk = static_cast<Eigen::Index>(k);
          H(kk, kk) = st[static_cast<std::size_t>(fr[k])].hess;
          min_diag = std::min(min_diag, H(kk, kk));
          max_diag = std::max(max_diag, std::abs(H(kk, kk)));
        }
        Eigen::LLT<Eigen::MatrixXd> llt;
        double mu = 0.0;
        bool ok = false;
        if (min_diag > 0.0) {
          llt.compute(H);
          ok = llt.info() == Eigen::Success;
        }
        if (!ok) {
          mu = std::max(prm_.shift * max_diag, -min_diag + prm_.shift * max_diag);
          if (!(mu > 0.0)) mu = std::numeric_limits<double>::min();
          for (int k = 0; k < 60 && !ok; ++k, mu *= 4.0) {
            Eigen::MatrixXd Hs = H;
            Hs.diagonal().array() += mu;
            llt.compute(Hs);
            ok = llt.info() == Eigen::Success;
          }
          ++shifted;
        }
        if (ok) {
          const Eigen::VectorXd dF = llt.solve(rhs);
          if (dF.allFinite()) {
            d(fr) = dF;
            newton = true;
          }
        }
        t_factor += since(tf);
      } else {
        newton = !ea.empty();
      }
      // ---- line search along the projection arc onto the piece boxes
      const auto ts = Clock::now();
      bool accepted = false;
      double Ft = F;
      if (newton && slope(st, d) < 0.0) {
        double t = 1.0;
        for (int k = 0; k < prm_.max_backtracks && !accepted; ++k, t *= prm_.backtrack) {
          if (evaluations(r) >= o_.max_evaluations) break;
          accepted = try_step(a, st, d, t, F, res, trial, qt, Ft, r);
        }
      }
      if (!accepted && evaluations(r) < o_.max_evaluations) {
        // scaled projected gradient: a descent path whenever the point is not stationary
        ++fallbacks;
        for (Eigen::Index i = 0; i < n_; ++i) {
          const NodeState& s = st[static_cast<std::size_t>(i)];
          d(i) = s.lo == s.hi ? 0.0 : -s.grad / scaling(i, s);
        }
        double t = 1.0;
        for (int k = 0; k < 80 && !accepted; ++k, t *= 0.5) {
          if (evaluations(r) >= o_.max_evaluations) break;
          accepted = try_step(a, st, d, t, F, res, trial, qt, Ft, r);
        }
      }
      t_search += since(ts);
      if (!accepted) {
        status = evaluations(r) >= o_.max_evaluations ? MinimizerStatus::evaluation_limit : MinimizerStatus::stalled;
        break;
      }
      const double level = roundoff_level(a, F);
      a.swap(trial);
      q_.swap(qt);
      const double decrease = F - Ft;
      F = Ft;
      res = residual(a, q_, r);
      ++r.iterations;
      // at round-off level steps may go on forever without improving the certificate
      stagnant = (decrease <= level && res >= best_res) ? stagnant + 1 : 0;
      best_res = std::min(best_res, res);
      const IterationRecord rec{r.iterations, F, res, feasibility(a), count_at_bound(a), since(t0)};
      r.history.push_back(rec);
      if (o_.callback && !o_.callback(rec)) {
        if (res > o_.tolerance) status = MinimizerStatus::stopped_by_callback;
        break;
      }
      if (stagnant >= 3 && res > o_.tolerance) {
        status = MinimizerStatus::stalled;
        break;
      }
    }
    r.a = std::move(a);
    r.timings["factorization"] = t_factor;
    r.timings["line_search"] = t_search;
    r.message = std::to_string(r.iterations) + " Newton iterations, " + std::to_string(fallbacks) +
                " gradient fallbacks, " + std::to_string(shifted) + " shifted systems";
    finish(p_, o_, status, r);
    if (status == MinimizerStatus::stalled && !r.converged())
      r.message = "no further descent at round-off level; " + r.message;
    r.timings["total"] = since(t0);
    return r;
  }

 private:
  static int evaluations(const MinimizerResult& r) { return r.function_evaluations + r.subgradient_evaluations; }

  double energy(const Eigen::VectorXd& a, Eigen::VectorXd* q, MinimizerResult& r) const {
    ++r.function_evaluations;
    *q = p_.S * a - p_.c;
    double f = 0.5 * a.dot(*q - p_.c);
    for (Eigen::Index i = 0; i < n_; ++i) f += p_.w(i) * p_.law->value(LawPart::j, a(i));
    return f;
  }

  /// The certificate's residual from q = S a - c (the same expression as certificate()).
  double residual(const Eigen::VectorXd& a, const Eigen::VectorXd& q, MinimizerResult& r) const {
    ++r.subgradient_evaluations;
    if (n_ == 0) return 0.0;
    double m = 0.0;
    for (Eigen::Index i = 0; i < n_; ++i) {
      const Interval dj = p_.law->clarke(a(i));
      const double xi = q(i) + p_.w(i) * dj.nearest(-q(i) / p_.w(i));
      const double pr = std::min(std::max(a(i) - xi, p_.lower(i)), p_.upper(i));
      m = std::max(m, std::abs(a(i) - pr));
    }
    return m / scale_;
  }

  double feasibility(const Eigen::VectorXd& a) const {
    return n_ == 0 ? 0.0 : (a - p_.project(a)).cwiseAbs().maxCoeff();
  }

  int count_at_bound(const Eigen::VectorXd& a) const {
    int k = 0;
    for (Eigen::Index i = 0; i < n_; ++i) k += (a(i) == p_.lower(i) || a(i) == p_.upper(i)) ? 1 : 0;
    return k;
  }

  bool is_kink(double x) const { return std::binary_search(kinks_.begin(), kinks_.end(), x); }
  double knot_above(Eigen::Index i, double x) const {
    const auto it = std::upper_bound(kinks_.begin(), kinks_.end(), x);
    return std::min(p_.upper(i), it == kinks_.end() ? kInf : *it);
  }
  double knot_below(Eigen::Index i, double x) const {
    const auto it = std::lower_bound(kinks_.begin(), kinks_.end(), x);
    return std::max(p_.lower(i), it == kinks_.begin() ? -kInf : *(it - 1));
  }

  /// The diagonal scaling of the gradient steps: the curvature on the side of motion, kept
  /// away from zero by a fraction of S_ii (S is positive definite).
  double scaling(Eigen::Index i, const NodeState& s) const {
    return std::max({s.hess, 1e-3 * p_.S(i, i), std::numeric_limits<double>::min()});
  }

  void classify(const Eigen::VectorXd& a, std::vector<NodeState>& st) const {
    for (Eigen::Index i = 0; i < n_; ++i) {
      NodeState& s = st[static_cast<std::size_t>(i)];
      const double x = a(i), l = p_.lower(i), u = p_.upper(i), wi = p_.w(i);
      if (x <= l || x >= u || is_kink(x)) {
        const double dr = x < u ? q_(i) + wi * p_.law->derivative(LawPart::j, x, +1) : kInf;
        const double dl = x > l ? q_(i) + wi * p_.law->derivative(LawPart::j, x, -1) : -kInf;
        const bool right = dr < 0.0, left = dl > 0.0;
        if (right && (!left || -dr >= dl)) {
          s.side = 1;
          s.lo = x;
          s.hi = knot_above(i, x);
          s.grad = dr;
        } else if (left) {
          s.side = -1;
          s.lo = knot_below(i, x);
          s.hi = x;
          s.grad = dl;
        } else {
          s.side = 1;
          s.lo = s.hi = x;
          s.grad = 0.0;
        }
      } else {
        s.grad = q_(i) + wi * p_.law->derivative(LawPart::j, x, +1);
        s.side = s.grad <= 0.0 ? 1 : -1;
        s.lo = knot_below(i, x);
        s.hi = knot_above(i, x);
      }
      s.hess = p_.S(i, i) + wi * p_.law->second_derivative(LawPart::j, x, s.side);
    }
  }

  /// The size of the rounding errors in F(a) (q_ = S a - c).
  double roundoff_level(const Eigen::VectorXd& a, double F) const {
    return 1e-12 * (std::abs(F) + 0.5 * std::abs(a.dot(q_ + p_.c)) + std::abs(p_.c.dot(a)));
  }

  static double slope(const std::vector<NodeState>& st, const Eigen::VectorXd& d) {
    double m = 0.0;
    for (std::size_t i = 0; i < st.size(); ++i) m += st[i].grad * d(static_cast<Eigen::Index>(i));
    return m;
  }

  /// Trial point P_box(a + t d); accepted on Armijo's condition, or, when the change of F is
  /// at round-off level, on a decrease of the certificate's residual.
  bool try_step(const Eigen::VectorXd& a, const std::vector<NodeState>& st, const Eigen::VectorXd& d, double t, double F,
                double res, Eigen::VectorXd& trial, Eigen::VectorXd& qt, double& Ft, MinimizerResult& r) const {
    double dec = 0.0;
    bool moved = false;
    for (Eigen::Index i = 0; i < n_; ++i) {
      const NodeState& s = st[static_cast<std::size_t>(i)];
      trial(i) = s.lo == s.hi ? a(i) : std::clamp(a(i) + t * d(i), s.lo, s.hi);
      const double step = trial(i) - a(i);
      moved = moved || step != 0.0;
      dec += s.grad * step;
    }
    if (!moved) return false;
    Ft = energy(trial, &qt, r);
    if (!std::isfinite(Ft)) return false;
    if (dec < 0.0 && Ft <= F + prm_.armijo * dec) return true;
    if (Ft <= F + roundoff_level(a, F)) return residual(trial, qt, r) < res;
    return false;
  }

  const ReducedProblem& p_;
  const MinimizerOptions& o_;
  const Parameters& prm_;
  const Eigen::Index n_;
  std::vector<double> kinks_;
  double scale_ = 1.0;
  Eigen::VectorXd q_;  ///< S a - c at the current point
};

}  // namespace

MinimizerResult SsnMinimizer::minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                                       const MinimizerOptions& options) const {
  const std::string where = "minimizer 'ssn'";
  std::string error;
  if (!options.is_valid(&error)) throw InputError(error, where);
  const Parameters prm = read_parameters(options);
  const Eigen::Index n = problem.size();
  if (!problem.law) throw InputError("the reduced problem has no contact law", where);
  if (problem.S.rows() != n || problem.S.cols() != n || problem.w.size() != n ||
      (problem.constraint != ConstraintKind::none && problem.g.size() != n))
    throw InputError("inconsistent sizes in the reduced problem", where);
  if (start.size() != 0 && start.size() != n)
    throw InputError("start has size " + std::to_string(start.size()) + ", expected " + std::to_string(n), where);
  if (start.size() != 0 && !start.allFinite()) throw InputError("start is not finite", where);
  Solver solver(problem, options, prm);
  return solver.run(start);
}

}  // namespace hemivem
