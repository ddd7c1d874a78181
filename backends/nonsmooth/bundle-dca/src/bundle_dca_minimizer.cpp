// The DC algorithm with a proximal bundle method for the convex subproblems (README.md).
#include <hemivem/bundle_dca_minimizer.hpp>

#include <hemivem/error.hpp>
#include <hemivem/minimizer_run.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

namespace hemivem {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- the cutting-plane model of one coordinate -------------------------------------------------
//
// A cut is the linearisation of phi_i(t) = w_i j1(t) at its base point: phi_i(x) >= f + s (x - t).
// Keeping the base point makes the breakpoints of the model computable to full precision: two
// cuts of a convex function with slopes s_a < s_b have base points t_a <= t_b and intersect in
// [t_a, t_b], so the computed intersection is clamped to that interval. (From intercepts alone
// the intersection of two nearby cuts loses all digits once (t_b - t_a)^2 j1'' is below the
// rounding of phi, which would stop the bundle method at a residual of about 1e-9.)

struct Cut {
  double t = 0.0;
  double f = 0.0;
  double slope = 0.0;
  double at(double x) const { return f + slope * (x - t); }
};

// The intersection of two cuts with a.slope < b.slope. When the linearisation error that fixes
// it is below the rounding of phi (cuts closer than about 1e-10), the midpoint of the base
// points is used: the intersection of the tangents of a quadratic, exact for the quadratic
// pieces of the shipped laws and within the interval in any case.
double intersection(const Cut& a, const Cut& b) {
  const double lo = std::min(a.t, b.t), hi = std::max(a.t, b.t);
  const double num = b.f - a.f - b.slope * (b.t - a.t);
  const double den = a.slope - b.slope;
  const double err = 8.0 * std::numeric_limits<double>::epsilon() *
                     (std::abs(a.f) + std::abs(b.f) + std::abs(b.slope * (b.t - a.t)));
  if (err > 0.25 * (hi - lo) * std::abs(den)) return 0.5 * (lo + hi);
  const double x = a.t + num / den;
  return std::min(std::max(x, lo), hi);
}

// The model psi_i of one coordinate restricted to [lo, hi]: the upper envelope of the cuts,
// piece k on [node[k], node[k+1]] with slope[k], given by cut index cut[k].
struct Envelope {
  std::vector<double> node;  // lo, interior breakpoints, hi (size pieces + 1)
  std::vector<double> slope;
  std::vector<int> cut;
  int pieces() const { return static_cast<int>(slope.size()); }
};

Envelope envelope(const std::vector<Cut>& cuts, double lo, double hi) {
  std::vector<int> order(cuts.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return cuts[a].slope < cuts[b].slope ||
           (cuts[a].slope == cuts[b].slope && cuts[a].at(cuts[b].t) > cuts[b].f);
  });
  std::vector<int> hull;
  std::vector<double> x;  // x[k]: intersection of hull[k] and hull[k+1]
  for (int l : order) {
    if (!hull.empty() && cuts[hull.back()].slope == cuts[l].slope) continue;  // same slope, lower
    double xl = 0.0;
    while (true) {
      if (hull.empty()) break;
      xl = intersection(cuts[hull.back()], cuts[l]);
      if (hull.size() >= 2 && xl <= x.back()) {  // the last line has an empty interval
        hull.pop_back();
        x.pop_back();
        continue;
      }
      break;
    }
    if (!hull.empty()) x.push_back(xl);
    hull.push_back(l);
  }
  std::size_t first = 0, last = hull.size() - 1;
  while (first < last && x[first] <= lo) ++first;
  while (last > first && x[last - 1] >= hi) --last;
  Envelope e;
  e.node.push_back(lo);
  for (std::size_t k = first; k <= last; ++k) {
    if (k > first) e.node.push_back(x[k - 1]);
    e.slope.push_back(cuts[hull[k]].slope);
    e.cut.push_back(hull[k]);
  }
  e.node.push_back(hi);
  return e;
}

// ---- the bundle subproblem: min 1/2 a^T H a - q^T a + sum_i psi_i(a_i), solved exactly ------
//
// A primal active-set method on the pieces of the separable polyhedral term: every coordinate
// is either free inside one piece (where psi_i is affine) or fixed at a node (a breakpoint of
// psi_i or a bound). On the current face the objective is a strictly convex quadratic: a
// Newton step with a ratio test keeps the iterate in the closure of its pieces (blocking
// coordinates become fixed at their node); at the face minimizer the multipliers
// r = q - H a of the fixed coordinates are checked against the subdifferential interval of the
// node, violators are released into the neighbouring piece. The objective decreases
// monotonically; the final point is exact up to rounding.
struct QpState {
  std::vector<char> fixed;
  std::vector<int> index;  // piece (free) or node (fixed)
};

struct QpStats {
  int steps = 0;
};

void locate(const std::vector<Envelope>& env, const Eigen::VectorXd& a, QpState& s) {
  const Eigen::Index n = a.size();
  s.fixed.assign(static_cast<std::size_t>(n), 0);
  s.index.assign(static_cast<std::size_t>(n), 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Envelope& e = env[static_cast<std::size_t>(i)];
    const double ai = a(i);
    int k = 0;
    while (k + 1 < e.pieces() && ai > e.node[static_cast<std::size_t>(k + 1)]) ++k;
    const double lo = e.node[static_cast<std::size_t>(k)], hi = e.node[static_cast<std::size_t>(k + 1)];
    const double eps = 1e-15 * (1.0 + std::abs(ai));
    if (std::isfinite(lo) && std::abs(ai - lo) <= eps) {
      s.fixed[static_cast<std::size_t>(i)] = 1;
      s.index[static_cast<std::size_t>(i)] = k;
    } else if (std::isfinite(hi) && std::abs(ai - hi) <= eps) {
      s.fixed[static_cast<std::size_t>(i)] = 1;
      s.index[static_cast<std::size_t>(i)] = k + 1;
    } else {
      s.index[static_cast<std::size_t>(i)] = k;
    }
  }
}

bool solve_qp(const Eigen::MatrixXd& H, const Eigen::VectorXd& q, const std::vector<std::vector<Cut>>& cuts,
              const std::vector<Envelope>& env, Eigen::VectorXd& a,
              QpState& s, QpStats& stats) {
  const Eigen::Index n = a.size();
  const auto U = [](Eigen::Index i) { return static_cast<std::size_t>(i); };
  // the start must lie in the closure of the pieces
  for (Eigen::Index i = 0; i < n; ++i) {
    const Envelope& e = env[U(i)];
    a(i) = std::min(std::max(a(i), e.node.front()), e.node.back());
  }
  locate(env, a, s);
  for (Eigen::Index i = 0; i < n; ++i)
    if (s.fixed[U(i)]) a(i) = env[U(i)].node[U(s.index[U(i)])];
  const double hscale = H.cwiseAbs().maxCoeff();
  auto model = [&](const Eigen::VectorXd& x) {  // the QP objective
    double v = 0.5 * x.dot(H * x) - q.dot(x);
    for (Eigen::Index i = 0; i < n; ++i) {
      double m = -kInf;
      for (int c : env[U(i)].cut) m = std::max(m, cuts[U(i)][U(c)].at(x(i)));
      v += m;
    }
    return v;
  };
  std::vector<Eigen::Index> released;  // released in the last multiplier check
  Eigen::Index most = -1;              // the most violating of them
  const int max_steps = 20 * static_cast<int>(n) + 100;
  for (int step = 0; step < max_steps; ++step) {
    ++stats.steps;
    std::vector<Eigen::Index> free;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!s.fixed[U(i)]) free.push_back(i);
    const Eigen::Index nf = static_cast<Eigen::Index>(free.size());
    double t = 1.0;
    std::vector<std::pair<Eigen::Index, double>> ratio;  // (coordinate, t_i) of blockers
    Eigen::VectorXd d(nf);
    if (nf > 0) {
      Eigen::MatrixXd Hff(nf, nf);
      Eigen::VectorXd rhs(nf);
      for (Eigen::Index r = 0; r < nf; ++r) {
        const Eigen::Index i = free[U(r)];
        for (Eigen::Index cidx = 0; cidx < nf; ++cidx) Hff(r, cidx) = H(i, free[U(cidx)]);
        double v = q(i) - env[U(i)].slope[U(s.index[U(i)])];
        for (Eigen::Index j = 0; j < n; ++j)
          if (s.fixed[U(j)]) v -= H(i, j) * a(j);
        rhs(r) = v;
      }
      const Eigen::LLT<Eigen::MatrixXd> llt(Hff);
      if (llt.info() != Eigen::Success) return false;  // S + mu I is not positive definite
      const Eigen::VectorXd z = llt.solve(rhs);
      if (!z.allFinite()) return false;
      for (Eigen::Index r = 0; r < nf; ++r) {
        const Eigen::Index i = free[U(r)];
        d(r) = z(r) - a(i);
        const Envelope& e = env[U(i)];
        const int k = s.index[U(i)];
        double ti = kInf;
        if (d(r) > 0.0 && std::isfinite(e.node[U(k + 1)])) ti = std::max(0.0, (e.node[U(k + 1)] - a(i)) / d(r));
        if (d(r) < 0.0 && std::isfinite(e.node[U(k)])) ti = std::max(0.0, (e.node[U(k)] - a(i)) / d(r));
        if (ti < 1.0) ratio.emplace_back(r, ti);
        t = std::min(t, ti);
      }
      // released coordinates that would block at once move back: keep them fixed, retry
      if (t <= 0.0 && released.size() > 1) {
        bool changed = false;
        for (const auto& [r, ti] : ratio) {
          const Eigen::Index i = free[U(r)];
          if (ti <= 0.0 && i != most && std::find(released.begin(), released.end(), i) != released.end()) {
            // back to the node it was released from
            const Envelope& e = env[U(i)];
            const int k = s.index[U(i)];
            s.fixed[U(i)] = 1;
            s.index[U(i)] = (a(i) == e.node[U(k)]) ? k : k + 1;
            changed = true;
          }
        }
        released.assign(1, most);
        if (changed) continue;
      }
      if (t < 1.0) {
        // the projected Newton point (every free coordinate clamped to its piece, those clamped
        // fixed at the node) is taken when it lowers the model at least as much as the
        // ratio-test step: many coordinates change state in one step instead of one
        Eigen::VectorXd proj = a, cut_step = a;
        for (Eigen::Index r = 0; r < nf; ++r) {
          const Eigen::Index i = free[U(r)];
          const Envelope& e = env[U(i)];
          const int k = s.index[U(i)];
          proj(i) = std::min(std::max(a(i) + d(r), e.node[U(k)]), e.node[U(k + 1)]);
          cut_step(i) = a(i) + t * d(r);
        }
        if (model(proj) <= model(cut_step)) {
          for (Eigen::Index r = 0; r < nf; ++r) {
            const Eigen::Index i = free[U(r)];
            const Envelope& e = env[U(i)];
            const int k = s.index[U(i)];
            if (proj(i) == e.node[U(k)] && std::isfinite(proj(i)) && d(r) < 0.0) {
              s.fixed[U(i)] = 1;
            } else if (proj(i) == e.node[U(k + 1)] && std::isfinite(proj(i)) && d(r) > 0.0) {
              s.fixed[U(i)] = 1;
              s.index[U(i)] = k + 1;
            }
          }
          a = proj;
          released.clear();
          most = -1;
          continue;
        }
      }
      for (Eigen::Index r = 0; r < nf; ++r) a(free[U(r)]) += t * d(r);
    }
    released.clear();
    most = -1;
    if (t < 1.0) {
      for (const auto& [r, ti] : ratio) {
        if (ti > t) continue;
        const Eigen::Index i = free[U(r)];
        const int k = s.index[U(i)];
        s.fixed[U(i)] = 1;
        s.index[U(i)] = d(r) > 0.0 ? k + 1 : k;
        a(i) = env[U(i)].node[U(s.index[U(i)])];
      }
      continue;
    }
    // face minimizer: check the multipliers of the fixed coordinates
    const Eigen::VectorXd r = q - H * a;
    const double tol = 1e-14 * (q.cwiseAbs().maxCoeff() + hscale * a.cwiseAbs().maxCoeff() + 1e-300);
    double worst = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!s.fixed[U(i)]) continue;
      const Envelope& e = env[U(i)];
      const int k = s.index[U(i)];
      const double lower = k > 0 ? e.slope[U(k - 1)] : -kInf;
      const double upper = k < e.pieces() ? e.slope[U(k)] : kInf;
      double v = 0.0;
      if (r(i) > upper + tol) {
        v = r(i) - upper;
        s.fixed[U(i)] = 0;
        s.index[U(i)] = k;
      } else if (r(i) < lower - tol) {
        v = lower - r(i);
        s.fixed[U(i)] = 0;
        s.index[U(i)] = k - 1;
      }
      if (v > 0.0) {
        released.push_back(i);
        if (v > worst) worst = v, most = i;
      }
    }
    if (released.empty()) return true;
  }
  return true;  // step cap reached: the point is feasible and no worse than the start
}

double model_value(const std::vector<std::vector<Cut>>& cuts, const Eigen::VectorXd& a) {
  double m = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    double v = -kInf;
    for (const Cut& c : cuts[static_cast<std::size_t>(i)]) v = std::max(v, c.at(a(i)));
    m += v;
  }
  return m;
}

// ---- the DC algorithm ---------------------------------------------------------------------------

// What one DC subproblem (the bundle loop) ended with.
struct SubproblemEnd {
  Eigen::VectorXd center;     // the last serious point
  bool model_exact = false;   // a null step that did not move: the model cannot improve
  bool out_of_budget = false;
  bool qp_failed = false;
};

class DcBundle {
 public:
  DcBundle(MinimizerRun& run, const BundleDcaOptions& options)
      : run_(run), p_(run.problem()), o_(options), n_(p_.size()), cuts_(U(n_)), added_(U(n_), 0) {
    mu_ = o_.proximal_weight * p_.S.diagonal().cwiseAbs().maxCoeff();
    H_ = p_.S;
    H_.diagonal().array() += mu_;
  }

  // The cuts of phi_i(t) = w_i j1(t) at a: one subgradient evaluation of F1.
  void add_cuts(const Eigen::VectorXd& a) {
    run_.count_subgradients();
    for (Eigen::Index i = 0; i < n_; ++i) {
      const double t = a(i);
      const double v = p_.w(i) * p_.law_of(i).value(LawPart::j1, t);
      const double sr = p_.w(i) * p_.law_of(i).derivative(LawPart::j1, t, +1);
      auto& ci = cuts_[U(i)];
      ci.push_back({t, v, sr});
      added_[U(i)] = 1;
      if (o_.two_sided_cuts) {
        const double sl = p_.w(i) * p_.law_of(i).derivative(LawPart::j1, t, -1);
        if (sl != sr) {
          ci.push_back({t, v, sl});
          added_[U(i)] = 2;
        }
      }
    }
  }

  // min_C F1 - y^T a from `center` by the proximal bundle method, to the inner tolerance.
  SubproblemEnd solve(const Eigen::VectorXd& start, const Eigen::VectorXd& y, double inner_tol) {
    SubproblemEnd end;
    end.center = start;
    Eigen::VectorXd& center = end.center;
    double fc = f1(center) - y.dot(center);
    double rc = residual(center, y);
    Eigen::VectorXd trial = center;
    const Eigen::VectorXd cy = p_.c + y;
    for (int it = 0; it < o_.max_bundle_iterations && rc > inner_tol; ++it) {
      if (!run_.budget_left(3)) {  // f_k and the cuts at the trial point, F at the end of the DC step
        end.out_of_budget = true;
        break;
      }
      ++bundle_iterations;
      std::vector<Envelope> env(U(n_));
      for (Eigen::Index i = 0; i < n_; ++i) env[U(i)] = envelope(cuts_[U(i)], p_.lower(i), p_.upper(i));
      QpStats qs;
      if (!solve_qp(H_, cy + mu_ * center, cuts_, env, trial, state_, qs)) {
        end.qp_failed = true;
        break;
      }
      qp_steps += qs.steps;
      double quad = 0.0;
      const double model = 0.5 * trial.dot(p_.S * trial) - cy.dot(trial) + model_value(cuts_, trial);
      const double predicted = fc - model;
      const double ft = f1(trial, &quad) - y.dot(trial);
      const double rt = residual(trial, y);
      add_cuts(trial);
      compress(env);
      for (const auto& ci : cuts_) largest_bundle = std::max(largest_bundle, ci.size());
      // near the solution the decrease is below the rounding of F (it is of the order of the
      // squared residual): there a trial no worse than the center up to rounding and with a
      // smaller residual is taken as a serious step too
      const double noise = 1e-13 * (std::abs(fc) + std::abs(quad) + 1e-300);
      if (ft <= fc - o_.descent * predicted || (ft <= fc + noise && rt < rc)) {
        ++serious_steps;
        center = trial;
        fc = ft;
        rc = rt;
      } else {
        ++null_steps;
        if ((trial - center).cwiseAbs().maxCoeff() <= 1e-15 * (1.0 + center.cwiseAbs().maxCoeff())) {
          end.model_exact = true;
          break;
        }
      }
    }
    return end;
  }

  int bundle_iterations = 0, serious_steps = 0, null_steps = 0, qp_steps = 0;
  std::size_t largest_bundle = 0;

 private:
  static std::size_t U(Eigen::Index i) { return static_cast<std::size_t>(i); }

  // F1(a), one function evaluation; the quadratic part in *quadratic_part.
  double f1(const Eigen::VectorXd& a, double* quadratic_part = nullptr) {
    run_.count_functions();
    const double qp = 0.5 * a.dot(p_.S * a) - p_.c.dot(a);
    if (quadratic_part) *quadratic_part = qp;
    double s = qp;
    for (Eigen::Index i = 0; i < n_; ++i) s += p_.w(i) * p_.law_of(i).value(LawPart::j1, a(i));
    return s;
  }

  // The dual residual of the DC subproblem min_C F1 - y^T a (the certificate's rule with j1
  // for j and c + y for c, at the point as it is).
  double residual(const Eigen::VectorXd& a, const Eigen::VectorXd& y) const {
    const Eigen::VectorXd Sa = p_.S * a;
    double worst = 0.0, scale = std::max((p_.c + y).cwiseAbs().maxCoeff(), Sa.cwiseAbs().maxCoeff());
    for (Eigen::Index i = 0; i < n_; ++i) {
      double dl = p_.law_of(i).derivative(LawPart::j1, a(i), -1), dr = p_.law_of(i).derivative(LawPart::j1, a(i), +1);
      if (dl > dr) std::swap(dl, dr);
      const Interval law{p_.w(i) * dl, p_.w(i) * dr};
      const Interval reaction{a(i) == p_.lower(i) ? -kInf : 0.0, a(i) == p_.upper(i) ? kInf : 0.0};
      double zeta = 0.0, lambda = 0.0;
      worst = std::max(worst, balance(Sa(i) - p_.c(i) - y(i), law, reaction, &zeta, &lambda));
      scale = std::max(scale, std::abs(zeta));
    }
    return worst == 0.0 ? 0.0 : worst / std::max(scale, force_floor);
  }

  // Keeps at most bundle_size cuts per coordinate: the active ones at the subproblem solution
  // (they carry the aggregate linearisation), the newest, then the most recent others.
  void compress(const std::vector<Envelope>& env) {
    for (Eigen::Index i = 0; i < n_; ++i) {
      auto& ci = cuts_[U(i)];
      if (static_cast<int>(ci.size()) <= o_.bundle_size) continue;
      std::vector<char> keep(ci.size(), 0);
      const Envelope& e = env[U(i)];
      const int k = state_.index[U(i)];
      if (state_.fixed[U(i)]) {
        if (k > 0) keep[U(e.cut[U(k - 1)])] = 1;
        if (k < e.pieces()) keep[U(e.cut[U(k)])] = 1;
      } else {
        keep[U(e.cut[U(k)])] = 1;
      }
      for (int j = 0; j < added_[U(i)]; ++j) keep[ci.size() - 1 - U(j)] = 1;
      int count = static_cast<int>(std::count(keep.begin(), keep.end(), 1));
      for (std::size_t j = ci.size(); j-- > 0 && count < o_.bundle_size;)
        if (!keep[j]) keep[j] = 1, ++count;
      std::vector<Cut> kept;
      for (std::size_t j = 0; j < ci.size(); ++j)
        if (keep[j]) kept.push_back(ci[j]);
      ci.swap(kept);
    }
  }

  MinimizerRun& run_;
  const ReducedProblem& p_;
  const BundleDcaOptions& o_;
  const Eigen::Index n_;
  double mu_ = 0.0;
  Eigen::MatrixXd H_;                   // S + mu I
  std::vector<std::vector<Cut>> cuts_;  // per coordinate
  std::vector<int> added_;              // cuts added last per coordinate (at the tail)
  QpState state_;
};

}  // namespace

MinimizerResult BundleDcaMinimizer::run(MinimizerRun& run) const {
  const ReducedProblem& p = run.problem();
  DcBundle bundle(run, options_);
  Eigen::VectorXd a = run.start();
  double F = p.energy(a);
  run.count_functions();
  Certificate cert = run.check(a);
  run.offer(a, cert);
  MinimizerStatus why = MinimizerStatus::iteration_limit;
  int no_progress = 0;
  const bool convex = p.all_laws_convex();
  std::string note;
  for (int k = 1; !cert.converged() && run.iterations_left(); ++k) {
    // a DC step costs the linearisation of F2, f_k at a_k, F at the end (and the first cut once)
    if (!run.budget_left(k == 1 ? 4 : 3)) {
      why = MinimizerStatus::evaluation_limit;
      break;
    }
    if (k == 1) bundle.add_cuts(a);
    // DC step: linearise F2 at a, solve min_C F1 - y^T a. With j convex (j2 = 0 for the shipped
    // convex laws) the subproblem is F itself, solved to the final accuracy at once.
    const Eigen::VectorXd y = p.subgradient_convex2(a);
    run.count_subgradients();
    const double floor = options_.inner_tolerance_floor * run.options().tolerance;
    const double inner_tol = convex ? floor : std::max(options_.inner_tolerance_factor * cert.worst(), floor);
    const SubproblemEnd end = bundle.solve(a, y, inner_tol);
    const Eigen::VectorXd previous = a;
    const double F_previous = F;
    const Certificate cert_previous = cert;
    a = end.center;
    F = p.energy(a);
    run.count_functions();
    cert = run.check(a);
    if (!run.record(a, F, cert)) {
      why = MinimizerStatus::stopped_by_callback;
      break;
    }
    if (cert.converged()) {
      why = MinimizerStatus::converged;
      break;
    }
    if (end.qp_failed) {
      why = MinimizerStatus::failed;
      note = "the bundle subproblem failed: S + mu I is not positive definite";
      break;
    }
    if (end.out_of_budget) {
      why = MinimizerStatus::evaluation_limit;
      break;
    }
    const bool progress = F < F_previous - 1e-15 * std::abs(F_previous) || cert.worst() < 0.9 * cert_previous.worst() ||
                          (a - previous).cwiseAbs().maxCoeff() > 1e-15 * (1.0 + a.cwiseAbs().maxCoeff());
    no_progress = progress ? 0 : no_progress + 1;
    if (no_progress >= options_.stall_iterations) {
      why = MinimizerStatus::stalled;
      note = end.model_exact ? "stalled: the bundle model is exact and the DC step no longer moves"
                             : "stalled: the DC step no longer moves";
      break;
    }
  }
  std::ostringstream msg;
  msg << run.iterations() << " DC iterations, " << bundle.bundle_iterations << " bundle iterations ("
      << bundle.serious_steps << " serious, " << bundle.null_steps << " null), " << bundle.qp_steps
      << " active-set steps, largest bundle " << bundle.largest_bundle << " cuts per node";
  return run.finish(why, note, msg.str());
}

}  // namespace hemivem
