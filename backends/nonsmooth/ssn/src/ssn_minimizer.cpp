// The semismooth Newton / active-set engine: see ssn_minimizer.hpp and README.md.
#include <hemivem/ssn_minimizer.hpp>
#include <hemivem/group_motion.hpp>
#include <hemivem/minimizer_run.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#if defined(HEMIVEM_SSN_WITH_LAPACK)
// LAPACK's Cholesky factorization (Fortran interface; the trailing length is that of the
// character argument, gfortran's hidden argument)
extern "C" void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t uplo_length);
#endif

namespace hemivem {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();
/// A Cholesky pivot^2 below this fraction of max |H_ii| is round-off: the system is singular.
constexpr double singular_pivot = 1e-13;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// H + shift I = L L^T for a dense symmetric H (its lower triangle is read), formed in the
/// factor's own storage: LAPACK's blocked dpotrf on the BLAS where it is found (2.6 times
/// Eigen's LLT on 2 303 x 2 303 here), Eigen's LLT otherwise. compute() is false when
/// H + shift I is not positive definite (a pivot <= 0 or NaN). The factor remembers the H it
/// was made from (in its strict upper triangle and a copy of the diagonal), so that
/// factors(H) tells, exactly, whether it is H's.
class DenseCholesky {
 public:
  bool compute(const Eigen::MatrixXd& H, double shift = 0.0) {
    diag_ = H.diagonal();
    shift_ = shift;
#if defined(HEMIVEM_SSN_WITH_LAPACK)
    if (H.rows() > 0 && H.rows() <= std::numeric_limits<int>::max() / 64) {
      L_ = H;
      L_.diagonal().array() += shift;
      const char uplo = 'L';
      const int n = static_cast<int>(H.rows());
      int info = 0;
      dpotrf_(&uplo, &n, L_.data(), &n, &info, 1);
      return info == 0;
    }
#endif
    L_.resize(0, 0);
    llt_.compute(H + shift * Eigen::MatrixXd::Identity(H.rows(), H.cols()));
    return llt_.info() == Eigen::Success;
  }
  /// The diagonal of L.
  Eigen::VectorXd diagonal() const {
    return L_.size() > 0 ? Eigen::VectorXd(L_.diagonal()) : Eigen::VectorXd(llt_.matrixLLT().diagonal());
  }
  /// The shift it was computed with.
  double shift() const noexcept { return shift_; }
  /// True when it was computed from exactly this H (bit for bit).
  bool factors(const Eigen::MatrixXd& H) const {
    if (H.rows() != diag_.size() || H.cols() != diag_.size() || H.diagonal() != diag_) return false;
    // the strict upper triangle of the factor's storage is the H it was made from
    const Eigen::MatrixXd& kept = L_.size() > 0 ? L_ : llt_.matrixLLT();
    for (Eigen::Index j = 1; j < H.cols(); ++j)
      if (H.col(j).head(j) != kept.col(j).head(j)) return false;
    return true;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    if (L_.size() == 0) return llt_.solve(b);
    Eigen::VectorXd x = b;
    L_.triangularView<Eigen::Lower>().solveInPlace(x);
    L_.triangularView<Eigen::Lower>().transpose().solveInPlace(x);
    return x;
  }

 private:
  Eigen::MatrixXd L_;                // dpotrf's factor (its upper triangle is H's)
  Eigen::LLT<Eigen::MatrixXd> llt_;  // without LAPACK (its upper triangle is H's too)
  Eigen::VectorXd diag_;             // H's diagonal
  double shift_ = 0.0;
};

}  // namespace

/// The last factor of a Newton system, kept for the next system when it is the same matrix (a
/// path's steps, and the iterations of one solve, mostly keep their free set).
struct SsnMinimizer::Memo {
  std::shared_ptr<const DenseCholesky> get() const {
    const std::lock_guard<std::mutex> lock(mutex);
    return last;
  }
  void set(std::shared_ptr<const DenseCholesky> factor) {
    const std::lock_guard<std::mutex> lock(mutex);
    last = std::move(factor);
  }
  mutable std::mutex mutex;
  std::shared_ptr<const DenseCholesky> last;
};

namespace {

/// What an iteration knows about one node.
struct NodeState {
  double lo = 0.0, hi = 0.0;  ///< its piece box (lo == hi: fixed)
  double grad = 0.0;          ///< one-sided derivative of F on the side of motion
  double hess = 0.0;          ///< S_ii + w_i j''(a_i, side)
  int side = 1;
};

/// What an iteration knows about one group of coordinates (hemivem/group_motion.hpp).
using GroupState = GroupMotion;

/// An unknown of the reduced Newton system: a coordinate, or a direction u in a group's plane.
struct Unknown {
  Eigen::Index first = 0, second = -1;  ///< second < 0: a single coordinate
  double u_first = 1.0, u_second = 0.0;
  double curvature = 0.0;  ///< the law's curvature along u (a coordinate's hess is its whole diagonal)
};

class Solver {
 public:
  Solver(MinimizerRun& run, const SsnOptions& prm, SsnMinimizer::Memo& memo)
      : run_(run), p_(run.problem()), prm_(prm), memo_(memo), n_(p_.size()), group_of_(p_.group_of()), gst_(p_.groups.size()) {
    for (int k = 0; k < p_.num_laws(); ++k) kinks_.push_back(p_.law_by_number(k).kinks());
  }

  MinimizerResult solve() {
    Eigen::VectorXd a = run_.start();
    double F = energy(a, &q_);
    double res = residual(a);
    run_.record_start(a, F, cert_);
    int stagnant = 0;
    double best_res = res;
    MinimizerStatus status = MinimizerStatus::converged;
    std::vector<NodeState> st(static_cast<std::size_t>(n_));
    Eigen::VectorXd d(n_), trial(n_), qt(n_);
    while (true) {
      if (cert_.converged()) break;
      if (!run_.iterations_left()) { status = MinimizerStatus::iteration_limit; break; }
      if (!run_.budget_left()) { status = MinimizerStatus::evaluation_limit; break; }
      classify(a, st);
      const bool newton = newton_direction(a, st, d);
      double Ft = F;
      if (!line_search(a, st, newton, F, res, d, trial, qt, Ft)) {
        status = run_.budget_left() ? MinimizerStatus::stalled : MinimizerStatus::evaluation_limit;
        break;
      }
      const double level = roundoff_level(a, F);
      a.swap(trial);
      q_.swap(qt);
      const double decrease = F - Ft;
      F = Ft;
      res = residual(a);
      // at round-off level steps may go on forever without improving the certificate
      stagnant = (decrease <= level && res >= best_res) ? stagnant + 1 : 0;
      best_res = std::min(best_res, res);
      if (!run_.record(a, F, cert_)) {
        if (!cert_.converged()) status = MinimizerStatus::stopped_by_callback;
        break;
      }
      if (stagnant >= 3 && !cert_.converged()) {
        status = MinimizerStatus::stalled;
        break;
      }
    }
    run_.add_time("factorization", t_factor_);
    run_.add_time("line_search", t_search_);
    const std::string summary = std::to_string(run_.iterations()) + " Newton iterations, " +
                                std::to_string(fallbacks_) + " gradient fallbacks, " + std::to_string(shifted_) +
                                " shifted systems";
    return run_.finish(status, status == MinimizerStatus::stalled ? "no further descent at round-off level" : "",
                       summary, &a);
  }

 private:
  double energy(const Eigen::VectorXd& a, Eigen::VectorXd* q) const {
    run_.count_functions();
    *q = p_.S * a - p_.c;
    double f = 0.5 * a.dot(*q - p_.c);
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (group_of_(i) >= 0) continue;
      f += p_.w(i) * p_.law_of(i).value(LawPart::j, a(i));
    }
    for (const CoordinateGroup& g : p_.groups) f += p_.w(g.first) * p_.law_of(g.first).value(LawPart::j, group_norm(a, g));
    return f;
  }

  /// The certificate at a (kept in cert_) and its worst residual.
  double residual(const Eigen::VectorXd& a) {
    run_.count_subgradients();
    cert_ = run_.check(a);
    return cert_.worst();
  }

  /// The projected Newton direction d: moving nodes within epsilon of a knot they are pushed
  /// against go onto it, the other moving nodes solve the free-set system. False when there is
  /// no usable Newton direction.
  bool newton_direction(const Eigen::VectorXd& a, const std::vector<NodeState>& st, Eigen::VectorXd& d) {
    double eps = 0.0;
    for (Eigen::Index i = 0; i < n_; ++i) {
      const NodeState& s = st[static_cast<std::size_t>(i)];
      if (s.lo == s.hi || group_of_(i) >= 0) continue;
      eps = std::max(eps, std::abs(std::clamp(a(i) - s.grad / scaling(i, s), s.lo, s.hi) - a(i)));
    }
    for (const GroupState& g : gst_) {
      if (g.mode == GroupState::Mode::stuck) continue;
      eps = std::max(eps, (group_trial(g, -g.grad / g.scale, 1.0) - g.v).norm());
    }
    eps *= prm_.active_scale;
    free_.clear();
    pinned_.clear();
    d.setZero();
    for (Eigen::Index i = 0; i < n_; ++i) {
      const NodeState& s = st[static_cast<std::size_t>(i)];
      if (s.lo == s.hi || group_of_(i) >= 0) continue;
      if (s.grad > 0.0 && a(i) - s.lo <= eps) {
        d(i) = s.lo - a(i);
        pinned_.push_back(i);
      } else if (s.grad < 0.0 && s.hi - a(i) <= eps) {
        d(i) = s.hi - a(i);
        pinned_.push_back(i);
      } else {
        free_.push_back(i);
      }
    }
    if (!p_.groups.empty()) return grouped_newton_direction(st, eps, d);
    if (free_.empty()) return !pinned_.empty();
    const auto tf = Clock::now();
    const bool ok = solve_free_system(st, d);
    t_factor_ += since(tf);
    return ok;
  }

  /// The groups' part of the projected Newton direction: a group within epsilon of a knot in
  /// radius that it is pushed against is sent onto it (onto 0 by d_G = -v, exactly), the other
  /// moving groups contribute their directions as unknowns; then the system of all unknowns.
  bool grouped_newton_direction(const std::vector<NodeState>& st, double eps, Eigen::VectorXd& d) {
    using Mode = GroupState::Mode;
    unknowns_.clear();
    for (Eigen::Index i : free_) unknowns_.push_back({i, -1, 1.0, 0.0, 0.0});
    bool pinned = !pinned_.empty();
    for (std::size_t k = 0; k < gst_.size(); ++k) {
      GroupState& g = gst_[k];
      const CoordinateGroup& grp = p_.groups[k];
      Eigen::Vector2d dg = Eigen::Vector2d::Zero();
      pin_group(g, eps);
      const auto add = [&](const Eigen::Vector2d& u, double curvature) {
        unknowns_.push_back({grp.first, grp.second, u(0), u(1), curvature});
      };
      switch (g.mode) {
        case Mode::stuck: break;
        case Mode::ray:
          if (std::isnan(g.pin)) add(g.e, g.radial_curvature);
          else dg = g.pin * g.e;
          break;
        case Mode::held: add(g.t, g.tangential_curvature); break;
        case Mode::plane:
          if (std::isnan(g.pin)) {
            add(g.e, g.radial_curvature);
            add(g.t, g.tangential_curvature);
          } else if (g.pin == 0.0) {
            dg = -g.v;
          } else {
            dg = (g.pin - g.r) * g.e;
            add(g.t, g.tangential_curvature);
          }
          break;
      }
      pinned = pinned || !std::isnan(g.pin);
      d(grp.first) = dg(0);
      d(grp.second) = dg(1);
    }
    if (unknowns_.empty()) return pinned;
    const auto tf = Clock::now();
    const bool ok = solve_unknowns_system(st, d);
    t_factor_ += since(tf);
    return ok;
  }

  /// u^T S u' for two unknowns.
  double coupling(const Unknown& u, const Unknown& v) const {
    double h = u.u_first * v.u_first * p_.S(u.first, v.first);
    if (v.second >= 0) h += u.u_first * v.u_second * p_.S(u.first, v.second);
    if (u.second >= 0) {
      h += u.u_second * v.u_first * p_.S(u.second, v.first);
      if (v.second >= 0) h += u.u_second * v.u_second * p_.S(u.second, v.second);
    }
    return h;
  }

  /// The reduced system over the unknowns (coordinates and directions in groups' planes):
  /// (U^T (S + W j'') U) x = -U^T (grad + S d_E), d = d_E + U x, shifted like the free-set system.
  bool solve_unknowns_system(const std::vector<NodeState>& st, Eigen::VectorXd& d) {
    const auto nf = static_cast<Eigen::Index>(unknowns_.size());
    const Eigen::VectorXd Sd = p_.S * d;
    Eigen::VectorXd rhs(nf);
    Eigen::MatrixXd H(nf, nf);
    double min_diag = kInf, max_diag = 0.0;
    for (Eigen::Index k = 0; k < nf; ++k) {
      const Unknown& u = unknowns_[static_cast<std::size_t>(k)];
      const auto grad = [&](Eigen::Index i) { return st[static_cast<std::size_t>(i)].grad + Sd(i); };
      rhs(k) = -u.u_first * grad(u.first) - (u.second >= 0 ? u.u_second * grad(u.second) : 0.0);
      for (Eigen::Index l = 0; l < k; ++l) H(k, l) = H(l, k) = coupling(u, unknowns_[static_cast<std::size_t>(l)]);
      const double elastic = u.second < 0 ? st[static_cast<std::size_t>(u.first)].hess : coupling(u, u);
      H(k, k) = elastic + u.curvature;
      min_diag = std::min(min_diag, H(k, k));
      // a positive curvature of the law only adds to a definite system: the round-off level of
      // its pivots is that of the rest (the tangential curvature j'(r)/r grows without bound at 0)
      max_diag = std::max(max_diag, std::abs(u.curvature > 0.0 ? elastic : H(k, k)));
    }
    Eigen::VectorXd x;
    if (!factor_and_solve(H, rhs, min_diag, max_diag, x)) return false;
    for (Eigen::Index k = 0; k < nf; ++k) {
      const Unknown& u = unknowns_[static_cast<std::size_t>(k)];
      d(u.first) += u.u_first * x(k);
      if (u.second >= 0) d(u.second) += u.u_second * x(k);
    }
    return true;
  }

  /// d_F = -(S + W j'')_FF^-1 (grad_F + S_FE d_E) by a dense LLT, shifted by mu I (growing from
  /// `shift` max |H_ii|) when the system is not positive definite or singular within round-off.
  bool solve_free_system(const std::vector<NodeState>& st, Eigen::VectorXd& d) {
    const auto nf = static_cast<Eigen::Index>(free_.size());
    Eigen::VectorXd rhs(nf);
    for (Eigen::Index k = 0; k < nf; ++k) rhs(k) = -st[static_cast<std::size_t>(free_[static_cast<std::size_t>(k)])].grad;
    if (!pinned_.empty()) rhs.noalias() -= p_.S(free_, pinned_) * d(pinned_);
    Eigen::MatrixXd H = p_.S(free_, free_);
    double min_diag = kInf, max_diag = 0.0;
    for (Eigen::Index k = 0; k < nf; ++k) {
      H(k, k) = st[static_cast<std::size_t>(free_[static_cast<std::size_t>(k)])].hess;
      min_diag = std::min(min_diag, H(k, k));
      max_diag = std::max(max_diag, std::abs(H(k, k)));
    }
    Eigen::VectorXd dF;
    if (!factor_and_solve(H, rhs, min_diag, max_diag, dF)) return false;
    d(free_) = dF;
    return true;
  }

  /// x = H^-1 rhs by a dense LLT, shifted by mu I (growing from `shift` max_diag) when H is not
  /// positive definite or singular within round-off (min_diag, max_diag: of H's diagonal).
  bool factor_and_solve(const Eigen::MatrixXd& H, const Eigen::VectorXd& rhs, double min_diag, double max_diag,
                        Eigen::VectorXd& x) {
    // the same H as the last system's (the free set did not change and the law's curvature is
    // the same): its factor, and the decisions taken on it, are those it would be made again
    std::shared_ptr<const DenseCholesky> kept = memo_.get();
    if (kept && kept->factors(H)) {
      if (kept->shift() > 0.0) ++shifted_;
      x = kept->solve(rhs);
      return x.allFinite();
    }
    kept.reset();
    memo_.set(nullptr);  // its memory is the new factor's
    auto llt = std::make_shared<DenseCholesky>();
    bool ok = false;
    if (min_diag > 0.0) {
      // a pivot at round-off level is a singular system (S is only semidefinite when a rigid
      // motion is free and the law does not stiffen the nodes that carry it): shifted too
      ok = llt->compute(H) && llt->diagonal().cwiseAbs2().minCoeff() > singular_pivot * max_diag;
    }
    if (!ok) {
      double mu = std::max(prm_.shift * max_diag, -min_diag + prm_.shift * max_diag);
      if (!(mu > 0.0)) mu = std::numeric_limits<double>::min();
      for (int k = 0; k < 60 && !ok; ++k, mu *= 4.0) ok = llt->compute(H, mu);
      ++shifted_;
    }
    if (!ok) return false;
    memo_.set(llt);
    x = llt->solve(rhs);
    return x.allFinite();
  }

  /// Backtracking along the projection arc onto the piece boxes: the Newton direction first,
  /// then a diagonally scaled projected-gradient step (a descent path whenever the point is not
  /// stationary). True when a trial point (trial, qt = S trial - c, Ft) was accepted.
  bool line_search(const Eigen::VectorXd& a, const std::vector<NodeState>& st, bool newton, double F, double res,
                   Eigen::VectorXd& d, Eigen::VectorXd& trial, Eigen::VectorXd& qt, double& Ft) {
    const auto ts = Clock::now();
    bool accepted = false;
    if (newton && slope(st, d) < 0.0) {
      double t = 1.0;
      for (int k = 0; k < prm_.max_backtracks && !accepted && run_.budget_left(); ++k, t *= prm_.backtrack)
        accepted = try_step(a, st, d, t, F, res, trial, qt, Ft);
    }
    if (!accepted && run_.budget_left()) {
      ++fallbacks_;
      for (Eigen::Index i = 0; i < n_; ++i) {
        const NodeState& s = st[static_cast<std::size_t>(i)];
        d(i) = s.lo == s.hi ? 0.0 : -s.grad / scaling(i, s);
      }
      for (std::size_t k = 0; k < gst_.size(); ++k) {
        GroupState& g = gst_[k];
        g.pin = std::numeric_limits<double>::quiet_NaN();
        const Eigen::Vector2d dg = g.mode == GroupState::Mode::stuck ? Eigen::Vector2d::Zero() : Eigen::Vector2d(-g.grad / g.scale);
        d(p_.groups[k].first) = dg(0);
        d(p_.groups[k].second) = dg(1);
      }
      double t = 1.0;
      for (int k = 0; k < 80 && !accepted && run_.budget_left(); ++k, t *= 0.5)
        accepted = try_step(a, st, d, t, F, res, trial, qt, Ft);
    }
    t_search_ += since(ts);
    return accepted;
  }

  const std::vector<double>& kinks(Eigen::Index i) const { return kinks_[static_cast<std::size_t>(p_.law_index(i))]; }
  bool is_kink(Eigen::Index i, double x) const { return std::binary_search(kinks(i).begin(), kinks(i).end(), x); }
  double knot_above(Eigen::Index i, double x) const {
    const auto it = std::upper_bound(kinks(i).begin(), kinks(i).end(), x);
    return std::min(p_.upper(i), it == kinks(i).end() ? kInf : *it);
  }
  double knot_below(Eigen::Index i, double x) const {
    const auto it = std::lower_bound(kinks(i).begin(), kinks(i).end(), x);
    return std::max(p_.lower(i), it == kinks(i).begin() ? -kInf : *(it - 1));
  }

  /// The diagonal scaling of the gradient steps: the curvature on the side of motion, kept
  /// away from zero by a fraction of S_ii (positive also where S is only semidefinite).
  double scaling(Eigen::Index i, const NodeState& s) const {
    return std::max({s.hess, 1e-3 * p_.S(i, i), std::numeric_limits<double>::min()});
  }

  void classify(const Eigen::VectorXd& a, std::vector<NodeState>& st) {
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (group_of_(i) >= 0) continue;
      NodeState& s = st[static_cast<std::size_t>(i)];
      const double x = a(i), l = p_.lower(i), u = p_.upper(i), wi = p_.w(i);
      const ContactLaw& law = p_.law_of(i);
      if (x <= l || x >= u || is_kink(i, x)) {
        const double dr = x < u ? q_(i) + wi * law.derivative(LawPart::j, x, +1) : kInf;
        const double dl = x > l ? q_(i) + wi * law.derivative(LawPart::j, x, -1) : -kInf;
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
        s.grad = q_(i) + wi * law.derivative(LawPart::j, x, +1);
        s.side = s.grad <= 0.0 ? 1 : -1;
        s.lo = knot_below(i, x);
        s.hi = knot_above(i, x);
      }
      s.hess = p_.S(i, i) + wi * law.second_derivative(LawPart::j, x, s.side);
    }
    for (std::size_t k = 0; k < gst_.size(); ++k) {
      const CoordinateGroup& grp = p_.groups[k];
      GroupState& g = gst_[k];
      g = group_motion(p_.law_of(grp.first), p_.w(grp.first), Eigen::Vector2d(a(grp.first), a(grp.second)),
                       Eigen::Vector2d(q_(grp.first), q_(grp.second)),
                       Eigen::Matrix2d{{p_.S(grp.first, grp.first), p_.S(grp.first, grp.second)},
                                       {p_.S(grp.second, grp.first), p_.S(grp.second, grp.second)}});
      for (const Eigen::Index i : {grp.first, grp.second}) {
        NodeState& s = st[static_cast<std::size_t>(i)];
        s.grad = g.grad(i == grp.first ? 0 : 1);
        s.lo = s.hi = 0.0;
        s.hess = 0.0;
        s.side = 1;
      }
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

  /// Trial point P_box(a + t d); accepted on Armijo's condition, or, when the change of F (or
  /// the decrease the condition asks for) is at round-off level, on a decrease of the
  /// certificate's residual.
  bool try_step(const Eigen::VectorXd& a, const std::vector<NodeState>& st, const Eigen::VectorXd& d, double t, double F,
                double res, Eigen::VectorXd& trial, Eigen::VectorXd& qt, double& Ft) {
    double dec = 0.0;
    bool moved = false;
    for (std::size_t k = 0; k < gst_.size(); ++k) {
      const CoordinateGroup& grp = p_.groups[k];
      const Eigen::Vector2d x = group_trial(gst_[k], Eigen::Vector2d(d(grp.first), d(grp.second)), t);
      trial(grp.first) = x(0);
      trial(grp.second) = x(1);
    }
    for (Eigen::Index i = 0; i < n_; ++i) {
      const NodeState& s = st[static_cast<std::size_t>(i)];
      if (group_of_(i) < 0) trial(i) = s.lo == s.hi ? a(i) : std::clamp(a(i) + t * d(i), s.lo, s.hi);
      const double step = trial(i) - a(i);
      moved = moved || step != 0.0;
      dec += s.grad * step;
    }
    if (!moved) return false;
    Ft = energy(trial, &qt);
    if (!std::isfinite(Ft)) return false;
    // Armijo's condition where the decrease it asks for is above F's round-off; below it the
    // comparison of F is noise, and a step must lower the residual instead
    const double level = roundoff_level(a, F);
    if (dec < -level && Ft <= F + prm_.armijo * dec && F - Ft > level) return true;
    if (Ft <= F + level) {
      const Certificate current = cert_;
      if (residual(trial) < res) return true;
      cert_ = current;
    }
    return false;
  }

  MinimizerRun& run_;
  const ReducedProblem& p_;
  const SsnOptions& prm_;
  SsnMinimizer::Memo& memo_;
  const Eigen::Index n_;
  const Eigen::VectorXi group_of_;  ///< per coordinate its group, -1 on its own
  std::vector<GroupState> gst_;     ///< per group
  std::vector<Unknown> unknowns_;   ///< of the reduced system when the problem has groups
  std::vector<std::vector<double>> kinks_;  ///< the kinks of each law
  Certificate cert_;   ///< at the current point (or the last trial point whose certificate was taken)
  std::vector<Eigen::Index> free_, pinned_;  ///< moving nodes solved for, and those sent onto a knot
  double t_factor_ = 0.0, t_search_ = 0.0;
  int fallbacks_ = 0, shifted_ = 0;
  Eigen::VectorXd q_;  ///< S a - c at the current point
};

}  // namespace

SsnMinimizer::SsnMinimizer(SsnOptions options) : options_(options), memo_(std::make_shared<Memo>()) {
  require_valid(options_, "ssn");
}

MinimizerResult SsnMinimizer::run(MinimizerRun& run) const { return Solver(run, options_, *memo_).solve(); }

}  // namespace hemivem
