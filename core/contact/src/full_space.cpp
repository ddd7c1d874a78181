// The full-space route: see hemivem/contact/full_space.hpp and docs/full-space.md.
#include <hemivem/contact/full_space.hpp>

#include <hemivem/certificate.hpp>
#include <hemivem/error.hpp>
#include <hemivem/existence.hpp>
#include <hemivem/group_motion.hpp>
#include <hemivem/minimizer_run.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace hemivem {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double armijo = 1e-4;
constexpr int max_backtracks = 30;
constexpr int max_gradient_backtracks = 80;
/// A group's curvature in a Newton system, w j'/r across a slipping node (unbounded as it comes to
/// rest), is taken at most this many times the group's stiffness: the system stays positive
/// definite and CG's preconditioners (an incomplete Cholesky factor) conditioned.
constexpr double max_group_curvature = 1e4;
/// A change of E below this fraction of the sizes of its terms is its round-off.
constexpr double energy_roundoff = 1e-12;
/// The Krylov tolerance of a Newton system: the square of the certificate's worst residual
/// (the inexact Newton method then keeps Newton's rate), within [krylov_floor, krylov_cap].
constexpr double krylov_floor = 1e-12;
constexpr double krylov_cap = 1e-4;
constexpr int max_krylov_iterations = 2000;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// One coordinate of the problem: its row, bounds, origin, law, weight and knots (its finite
/// bounds and its law's kinks between them, increasing).
struct Coordinate {
  int row = 0;
  double lo = 0.0, hi = 0.0, origin = 0.0, w = 0.0;
  const ContactLaw* law = nullptr;
  int group = -1;  ///< its group (ReducedProblem::groups), -1 on its own
  std::vector<double> knots;
  /// The largest knot below a and the smallest above (+-inf where there is none).
  double knot_below(double a) const {
    const auto it = std::lower_bound(knots.begin(), knots.end(), a);
    return it == knots.begin() ? -kInf : *(it - 1);
  }
  double knot_above(double a) const {
    const auto it = std::upper_bound(knots.begin(), knots.end(), a);
    return it == knots.end() ? kInf : *it;
  }
  bool on_knot(double a) const { return std::binary_search(knots.begin(), knots.end(), a); }
};

/// What an iteration knows about one coordinate.
struct Motion {
  bool held = false;          ///< on a knot, where the one-sided derivatives keep it
  double lo = 0.0, hi = 0.0;  ///< its piece box
  double grad = 0.0;          ///< the derivative of E along it on the side of motion
  double curvature = 0.0;     ///< w j''(a, side)
  double step = 0.0;          ///< a step prescribed onto a knot (epsilon-active)
  bool pushed = false;
};

/// What an iteration knows about every coordinate on its own and every group of two.
struct Motions {
  std::vector<Motion> coordinate;  ///< per coordinate (unused for a group's)
  std::vector<GroupMotion> group;  ///< per group, in ReducedProblem::groups order
};

/// A group of two coordinates (a solid's isotropic friction): its rows, A's block on them, and
/// where the pairs of its two rows' entries lie in A's values (the two unknowns of one node share
/// the pattern: hemivem/contact/condensation.hpp), in each column and in its own two columns.
struct Group {
  int first = 0, second = 0;  ///< coordinates
  int row1 = 0, row2 = 0;
  Eigen::Matrix2d block = Eigen::Matrix2d::Zero();
  std::vector<std::pair<Eigen::Index, Eigen::Index>> in_columns, columns;
};

/// What the iteration reads of a process's rows of a posed problem (FullSpaceShare, or the whole
/// posed problem in one process, without a copy).
struct ShareView {
  const SparseMatrix& A;
  const Eigen::VectorXd& b;
  const ReducedProblem& coordinates;
  std::vector<int> rows;  ///< each coordinate's row
  const Eigen::VectorXd& origin;
  std::vector<int> tied;
  /// A itself, lent to the iteration (minimize_full_space_in_place), or null.
  SparseMatrix* lent = nullptr;
  /// The rigid motions A leaves free (Condensation::free_motions()), or null.
  const Eigen::MatrixXd* free_motions = nullptr;
  /// Each coordinate's number in the whole problem (FullSpaceShare::coordinate_numbers), or null:
  /// the coordinates are the whole problem's.
  const std::vector<Eigen::Index>* numbers = nullptr;
};

ShareView whole(const Condensation& posed, const ReducedProblem& coordinates, const Eigen::VectorXd& origin) {
  if (coordinates.size() != posed.reduced().size())
    throw InternalError("the full-space route needs the posed problem's coordinates");
  std::vector<int> rows(static_cast<std::size_t>(coordinates.size()));
  for (Eigen::Index k = 0; k < coordinates.size(); ++k) rows[static_cast<std::size_t>(k)] = posed.rotated_index(k);
  return {posed.rotated_matrix(), posed.rotated_load(), coordinates, std::move(rows), origin, posed.tied_rows(),
          nullptr,  posed.free_motions().cols() > 0 ? &posed.free_motions() : nullptr};
}

class FullSpaceNewton {
 public:
  /// The rows of `view` on the processes `all` (one process: the whole system).
  FullSpaceNewton(const ShareView& view, const RowDistribution& all, double tol)
      : p_(view.coordinates), A_(view.A), lent_(view.lent), b_(view.b), all_(all), tol_(tol) {
    // every process decides alike, so that none is left waiting in a collective call
    const bool unfit = view.rows.size() != static_cast<std::size_t>(p_.size()) || view.origin.size() != p_.size() ||
                       A_.rows() != b_.size() || A_.rows() != all.layout().owned || A_.cols() != all.columns();
    if (all.max(unfit ? 1.0 : 0.0) > 0.0 || all.sum(static_cast<double>(A_.rows())) == 0.0)
      throw InternalError("the full-space route needs a posed problem distributed by its rows, with a row and an "
                          "origin for each coordinate");
    const Eigen::Index m = p_.size();
    coordinates_.resize(static_cast<std::size_t>(m));
    stiffness_.resize(m);
    load_.resize(m);
    is_coordinate_.assign(static_cast<std::size_t>(A_.rows()), 0);
    for (Eigen::Index k = 0; k < m; ++k) {
      Coordinate& c = coordinates_[static_cast<std::size_t>(k)];
      c.row = view.rows[static_cast<std::size_t>(k)];
      c.lo = p_.lower(k);
      c.hi = p_.upper(k);
      c.origin = view.origin(k);
      c.w = p_.w(k);
      c.law = &p_.law_of(k);
      for (double b : {c.lo, c.hi})
        if (std::isfinite(b)) c.knots.push_back(b);
      for (double kink : c.law->kinks())
        if (kink >= c.lo && kink <= c.hi) c.knots.push_back(kink);
      std::sort(c.knots.begin(), c.knots.end());
      c.knots.erase(std::unique(c.knots.begin(), c.knots.end()), c.knots.end());
      stiffness_(k) = A_.coeff(c.row, c.row);
      load_(k) = b_(c.row);
      is_coordinate_[static_cast<std::size_t>(c.row)] = 1;
    }
    for (int row : view.tied) {
      tied_.push_back(row);
      is_coordinate_[static_cast<std::size_t>(row)] = 2;
    }
    // the groups' places, each a decision of every process alike (a throw of one process would
    // leave the others waiting in a collective call)
    const auto agreed = [&all](const std::function<void()>& find) {
      std::string broken;
      try {
        find();
      } catch (const InternalError& e) {
        broken = e.what();
      }
      if (all.max(broken.empty() ? 0.0 : 1.0) > 0.0)
        throw InternalError(broken.empty() ? "a group's unknowns do not share their pattern on another process"
                                           : broken);
    };
    if (all.max(view.free_motions ? 1.0 : 0.0) > 0.0) {
      const bool fit = view.free_motions && view.free_motions->rows() == A_.rows() &&
                       (all.size() == 1 || (view.numbers && view.numbers->size() == static_cast<std::size_t>(m)));
      const double motions = fit ? static_cast<double>(view.free_motions->cols()) : -1.0;
      if (all.min(motions) < 0.0 || all.min(motions) != all.max(motions))
        throw InternalError("free motions of another problem's unknowns");
      free_motions_ = view.free_motions;
      numbers_ = all.size() > 1 ? view.numbers : nullptr;  // one process holds the whole problem
      for (Eigen::Index k = 0; k < m; ++k) proximal_ = std::max(proximal_, stiffness_(k));
      proximal_ = all.max(proximal_);
    }
    agreed([this] { find_groups(); });
    any_groups_ = all.max(groups_.empty() ? 0.0 : 1.0) > 0.0;
    if (all.size() > 1 && any_groups_) agreed([this] { find_ghost_groups(); });
  }

  Eigen::VectorXd coordinates_of(const Eigen::VectorXd& x) const {
    Eigen::VectorXd a(p_.size());
    for (std::size_t k = 0; k < coordinates_.size(); ++k)
      a(static_cast<Eigen::Index>(k)) = x(coordinates_[k].row) - coordinates_[k].origin;
    return a;
  }
  void put_coordinates(const Eigen::VectorXd& a, Eigen::VectorXd& x) const {
    for (std::size_t k = 0; k < coordinates_.size(); ++k)
      x(coordinates_[k].row) = a(static_cast<Eigen::Index>(k)) + coordinates_[k].origin;
  }
  /// A v of the owned entries v: the ghosts' entries from their owners first.
  Eigen::VectorXd multiply(const Eigen::VectorXd& v) const {
    if (all_.size() == 1) return A_ * v;  // every process decides alike: update_ghosts is collective
    Eigen::VectorXd extended = Eigen::VectorXd::Zero(A_.cols());
    extended.head(v.size()) = v;
    all_.update_ghosts(extended);
    return A_ * extended;
  }
  /// Flags of the owned rows, and of the ghosts from their owners.
  std::vector<char> with_ghosts(const std::vector<char>& owned) const {
    if (all_.size() == 1) return owned;
    Eigen::VectorXd v = Eigen::VectorXd::Zero(A_.cols());
    for (std::size_t i = 0; i < owned.size(); ++i) v(static_cast<Eigen::Index>(i)) = owned[i];
    all_.update_ghosts(v);
    std::vector<char> flags(static_cast<std::size_t>(v.size()));
    for (Eigen::Index i = 0; i < v.size(); ++i) flags[static_cast<std::size_t>(i)] = v(i) != 0.0 ? 1 : 0;
    return flags;
  }

  /// The residual A x - b, 0 at the tied rows (their reactions).
  Eigen::VectorXd residual(const Eigen::VectorXd& x, Eigen::VectorXd* Ax = nullptr) const {
    Eigen::VectorXd Axv = multiply(x);
    Eigen::VectorXd r = Axv - b_;
    for (int row : tied_) r(row) = 0.0;
    if (Ax) *Ax = std::move(Axv);
    return r;
  }
  double energy(const Eigen::VectorXd& x, const Eigen::VectorXd& Ax, double* size = nullptr) const {
    const double quadratic = all_.sum(0.5 * x.dot(Ax)), linear = all_.sum(b_.dot(x));
    const Eigen::VectorXd a = coordinates_of(x);
    const double law = all_.sum(p_.law_energy(a, 0.0));
    if (size) {
      double s = 0.0;
      for (Eigen::Index k = 0; k < a.size(); ++k) s += std::abs(p_.w(k) * p_.law_of(k).value(a(k)));
      *size = std::abs(quadratic) + std::abs(linear) + all_.sum(s);
    }
    return quadratic - linear + law;
  }

  CertifiedPoint certify(const Eigen::VectorXd& x) const {
    const double bmax = b_.size() ? b_.cwiseAbs().maxCoeff() : 0.0;
    return hemivem::certify(
        p_, coordinates_of(x), tol_,
        [&](const Eigen::VectorXd& a) {
          Eigen::VectorXd xs = x;
          put_coordinates(a, xs);
          Eigen::VectorXd Ax;
          const Eigen::VectorXd r = residual(xs, &Ax);
          SmoothGradient g;
          g.r.resize(a.size());
          for (std::size_t k = 0; k < coordinates_.size(); ++k)
            g.r(static_cast<Eigen::Index>(k)) = r(coordinates_[k].row);
          for (Eigen::Index i = 0; i < r.size(); ++i)
            if (!is_coordinate_[static_cast<std::size_t>(i)]) g.other = std::max(g.other, std::abs(r(i)));
          double axmax = 0.0;
          for (Eigen::Index i = 0; i < Ax.size(); ++i)
            if (is_coordinate_[static_cast<std::size_t>(i)] != 2) axmax = std::max(axmax, std::abs(Ax(i)));
          g.force_size = std::max(bmax, axmax);
          return g;
        },
        stiffness_, load_, all_.size() > 1 ? &all_ : nullptr);
  }

  MinimizerResult run(KrylovSolver& krylov, const KrylovHints& hints, const MinimizerOptions& options,
                      Eigen::VectorXd* x_io, FullSpaceStatistics* stats) {
    const auto t0 = Clock::now();
    const Eigen::Index n = A_.rows();
    Eigen::VectorXd x = x_io->size() == n ? *x_io : Eigen::VectorXd::Zero(n);
    for (int row : tied_) x(row) = 0.0;
    {
      Eigen::VectorXd a = coordinates_of(x);
      for (std::size_t k = 0; k < coordinates_.size(); ++k)
        a(static_cast<Eigen::Index>(k)) = std::clamp(a(static_cast<Eigen::Index>(k)), coordinates_[k].lo, coordinates_[k].hi);
      put_coordinates(a, x);
    }
    MinimizerResult result;
    FullSpaceStatistics local;
    FullSpaceStatistics& st = stats ? *stats : local;
    std::string why;
    MinimizerStatus status = MinimizerStatus::iteration_limit;
    CertifiedPoint point = certify(x);
    Counts counts;
    SystemCache cache;
    if (free_motions_ && options.check_existence) {
      const Existence e = existence();
      if (!e.bounded) {
        *x_io = std::move(x);
        return finish(krylov.name(), MinimizerStatus::unbounded, e.message, point, counts, st, t0, x_io,
                      std::move(result));
      }
    }
    for (int it = 0;; ++it) {
      Eigen::VectorXd Ax;
      const Eigen::VectorXd r = residual(x, &Ax);
      double scale = 0.0;  // the sizes of E's terms, for its round-off
      const double E = energy(x, Ax, &scale);
      record(result, it, E, point.certificate, x, t0);
      if (options.callback && it > 0 && !options.callback(result.history.back())) {
        status = MinimizerStatus::stopped_by_callback;
        break;
      }
      if (point.certificate.converged()) {
        status = MinimizerStatus::converged;
        break;
      }
      if (it >= options.max_iterations) break;
      // the motions and the Newton system
      const Motions motion = classify(x, r);
      Eigen::VectorXd grad = r;  // the gradient of E on the side of motion, for Armijo's rule
      for (std::size_t k = 0; k < coordinates_.size(); ++k) grad(coordinates_[k].row) = motion.coordinate[k].grad;
      for (std::size_t k = 0; k < groups_.size(); ++k) {
        grad(groups_[k].row1) = motion.group[k].grad(0);
        grad(groups_[k].row2) = motion.group[k].grad(1);
      }
      Eigen::VectorXd step;
      if (!descent_direction(krylov, hints, motion, r, grad, point.certificate.worst(), st, cache, &step, &why)) {
        status = MinimizerStatus::failed;
        break;
      }
      ++st.newton_iterations;
      if (!line_search(motion, grad, step, E, scale, x, point, counts)) {
        // a scaled gradient step along the projection arc, a direction of descent wherever the
        // point is not critical (an inexact Newton direction through a group's cone point may not be)
        Motions unpinned = motion;
        const Eigen::VectorXd gradient_step = scaled_gradient_step(unpinned, grad);
        if (!line_search(unpinned, grad, gradient_step, E, scale, x, point, counts, max_gradient_backtracks)) {
          status = MinimizerStatus::stalled;
          why = "no step along the Newton direction or the gradient lowered the energy or the certificate's residual";
          break;
        }
        ++counts.gradient_steps;
      }
    }
    *x_io = std::move(x);
    return finish(krylov.name(), status, why, point, counts, st, t0, x_io, std::move(result));
  }

 private:
  /// The last Newton system's held unknowns and curvatures: a system equal to it keeps its
  /// preconditioner.
  /// Puts the values `changed` back into `matrix` (when not null): by restore(), or at the end of
  /// its scope at the latest.
  struct RestoreValues {
    SparseMatrix* matrix;
    std::vector<std::pair<Eigen::Index, double>> changed;
    explicit RestoreValues(SparseMatrix* m) : matrix(m) {}
    RestoreValues(const RestoreValues&) = delete;
    RestoreValues& operator=(const RestoreValues&) = delete;
    void restore() {
      if (matrix)
        for (auto it = changed.rbegin(); it != changed.rend(); ++it) matrix->valuePtr()[it->first] = it->second;
      changed.clear();
    }
    ~RestoreValues() { restore(); }
  };
  struct SystemCache {
    std::vector<char> eliminated;
    Eigen::VectorXd shift;
    Eigen::VectorXd frames;  ///< each group's e
    /// The Newton matrix, one object for the whole iteration: the Krylov engine may read it
    /// where it lies, and a system of the same pattern keeps what its preconditioner can.
    SparseMatrix H;
  };
  struct NewtonOutcome {
    std::string why;     ///< empty: solved
    bool fatal = false;  ///< a preconditioner that failed: no retry
  };

  /// Energies and certificates evaluated.
  struct Counts {
    int functions = 0, certificates = 1, gradient_steps = 0;
  };

  // -grad scaled by the diagonal of E's generalized Hessian (a coordinate's curvature on its side
  // of motion, a group's along its direction of motion, A's diagonal elsewhere), none for the
  // held coordinates and stuck groups; the groups' and coordinates' pins released.
  Eigen::VectorXd scaled_gradient_step(Motions& motion, const Eigen::VectorXd& grad) const {
    Eigen::VectorXd d(A_.rows());
    const Eigen::VectorXd diagonal = A_.diagonal();
    for (Eigen::Index i = 0; i < d.size(); ++i) d(i) = diagonal(i) > 0.0 ? -grad(i) / diagonal(i) : 0.0;
    for (int row : tied_) d(row) = 0.0;
    for (std::size_t k = 0; k < coordinates_.size(); ++k) {
      Motion& mk = motion.coordinate[k];
      const int row = coordinates_[k].row;
      mk.pushed = false;
      const double curvature = stiffness_(static_cast<Eigen::Index>(k)) + std::max(0.0, mk.curvature);
      d(row) = mk.held || !(curvature > 0.0) ? 0.0 : -mk.grad / curvature;
    }
    for (std::size_t k = 0; k < groups_.size(); ++k) {
      GroupMotion& g = motion.group[k];
      g.pin = std::numeric_limits<double>::quiet_NaN();
      const Eigen::Vector2d dg = g.mode == GroupMotion::Mode::stuck ? Eigen::Vector2d::Zero() : Eigen::Vector2d(-g.grad / g.scale);
      d(groups_[k].row1) = dg(0);
      d(groups_[k].row2) = dg(1);
    }
    return d;
  }

  // The step of a Newton iteration: the law's own curvature first (Newton's rate; the system is
  // positive definite wherever the problem is strongly convex), its negative part left out when
  // CG meets an indefinite system or the step does not descend. False (and *why) when there is
  // no direction of descent.
  bool descent_direction(KrylovSolver& krylov, const KrylovHints& hints, const Motions& motion,
                         const Eigen::VectorXd& r, const Eigen::VectorXd& grad, double worst, FullSpaceStatistics& st,
                         SystemCache& cache, Eigen::VectorXd* step, std::string* why) const {
    bool concave = false;
    for (const Motion& mk : motion.coordinate) concave = concave || (!mk.held && !mk.pushed && mk.curvature < 0.0);
    for (const GroupMotion& g : motion.group)
      concave = concave || (g.mode != GroupMotion::Mode::stuck && std::isnan(g.pin) && g.radial_curvature < 0.0);
    concave = all_.max(concave ? 1.0 : 0.0) > 0.0;
    for (const bool clip : {false, true}) {
      if (clip && !concave) break;
      const NewtonOutcome o = newton_step(krylov, hints, motion, r, clip, worst, st, cache, step);
      if (!o.why.empty()) {
        *why = o.why;
        if (o.fatal || clip || !concave) return false;
        continue;
      }
      if (all_.sum(grad.dot(*step)) < 0.0 || clip || !concave) {
        why->clear();
        return true;
      }
    }
    if (why->empty()) *why = "the Newton step is not a direction of descent";
    return false;
  }

  // Backtracking along the projection arc from x (E0 = E(x), `scale` the sizes of its terms)
  // with Armijo's rule on E, or where E cannot tell (a change within its round-off) by the
  // certificate's residual. On success x and its certified point move to the step taken.
  bool line_search(const Motions& motion, const Eigen::VectorXd& grad, const Eigen::VectorXd& step,
                   double E0, double scale, Eigen::VectorXd& x, CertifiedPoint& point, Counts& counts,
                   int backtracks = max_backtracks) const {
    double t = 1.0;
    for (int bt = 0; bt <= backtracks; ++bt, t *= 0.5) {
      Eigen::VectorXd xt = x + t * step;
      for (std::size_t k = 0; k < groups_.size(); ++k) {
        const Group& g = groups_[k];
        const Eigen::Vector2d y = group_trial(motion.group[k], Eigen::Vector2d(step(g.row1), step(g.row2)), t);
        xt(g.row1) = y(0) + coordinates_[static_cast<std::size_t>(g.first)].origin;
        xt(g.row2) = y(1) + coordinates_[static_cast<std::size_t>(g.second)].origin;
      }
      for (std::size_t k = 0; k < coordinates_.size(); ++k) {
        const Coordinate& c = coordinates_[k];
        const Motion& mk = motion.coordinate[k];
        if (c.group >= 0) continue;
        if (mk.held)
          xt(c.row) = x(c.row);
        else if (mk.pushed && t == 1.0)
          xt(c.row) = x(c.row) + mk.step;  // exactly onto its knot
        else
          xt(c.row) = std::clamp(xt(c.row) - c.origin, mk.lo, mk.hi) + c.origin;
      }
      for (int row : tied_) xt(row) = 0.0;
      Eigen::VectorXd Axt;
      residual(xt, &Axt);
      const double E1 = energy(xt, Axt);
      ++counts.functions;
      const double predicted = all_.sum(grad.dot(xt - x));
      if (std::abs(E1 - E0) <= energy_roundoff * scale || std::abs(predicted) <= energy_roundoff * scale) {
        CertifiedPoint trial = certify(xt);
        ++counts.certificates;
        if (trial.certificate.worst() < point.certificate.worst()) {
          x = std::move(xt);
          point = std::move(trial);
          return true;
        }
      } else if (E1 <= E0 + armijo * predicted) {
        x = std::move(xt);
        point = certify(x);
        ++counts.certificates;
        return true;
      }
    }
    return false;
  }

  // The report at the certified point: its coordinates put into x (the snapped point is the one
  // certified), the forces, counts, status and message.
  MinimizerResult finish(const std::string& engine, MinimizerStatus status, const std::string& why,
                         const CertifiedPoint& point, const Counts& counts, const FullSpaceStatistics& st,
                         Clock::time_point t0, Eigen::VectorXd* x_io, MinimizerResult result) const {
    if (all_.max(point.a.size() != p_.size() ? 1.0 : 0.0) > 0.0)
      throw NumericalError("the full-space iteration reached a point that is not finite" +
                           (why.empty() ? std::string() : ": " + why));
    put_coordinates(point.a, *x_io);
    Eigen::VectorXd Ax;
    residual(*x_io, &Ax);
    result.a = point.a;
    result.law_force = point.law_force;
    result.reaction = point.reaction;
    result.certificate = point.certificate;
    result.objective = energy(*x_io, Ax);
    result.iterations = st.newton_iterations;
    result.function_evaluations = counts.functions;
    result.subgradient_evaluations = counts.certificates;
    // convex laws prove uniqueness where A is definite; a semi-coercive problem's F is convex but
    // not strictly along its free motions
    result.may_be_nonunique = all_.max(p_.all_laws_convex() && !free_motions_ ? 0.0 : 1.0) > 0.0;
    result.status = point.certificate.converged()
                        ? MinimizerStatus::converged
                        : (status == MinimizerStatus::converged ? MinimizerStatus::stalled : status);
    const std::string summary = std::to_string(st.newton_iterations) + " Newton iterations, " +
                                std::to_string(st.krylov_iterations) + " " + engine + " iterations" +
                                (counts.gradient_steps > 0 ? ", " + std::to_string(counts.gradient_steps) + " gradient steps"
                                                           : std::string());
    result.message =
        result.converged() ? summary : (why.empty() ? "the iteration limit was reached" : why) + "; " + summary;
    result.timings["total"] = since(t0);
    result.timings["preconditioner"] = st.preconditioner_seconds;
    result.timings["krylov"] = st.krylov_seconds;
    return result;
  }

  /// True when the Newton systems are written into the lent matrix itself: on several processes,
  /// with an engine that distributes the system (KrylovSolver::runs_across_processes()) and
  /// no groups, instead of a second matrix of the share's size.
  bool writes_in_place(const KrylovSolver& krylov) const {
    return lent_ && all_.size() > 1 && krylov.runs_across_processes() && !any_groups_;
  }

  // The Newton matrix (A's rows in the groups' frames, the eliminated rows and columns the
  // identity's, the curvature shifts on the diagonal): written into the lent matrix itself, the
  // values it changes (those of the contact rows and columns) kept in `restore`, where
  // writes_in_place(); otherwise into cache.H. Returns the matrix written.
  const SparseMatrix& write_newton_matrix(const Motions& motion, const std::vector<char>& eliminated,
                                          const Eigen::VectorXd& shift, bool in_place, SystemCache& cache,
                                          RestoreValues& restore) const {
    SparseMatrix& H = in_place ? *lent_ : cache.H;
    if (!in_place) {
      if (H.nonZeros() != A_.nonZeros() || H.rows() != A_.rows())
        H = A_;
      else
        std::copy(A_.valuePtr(), A_.valuePtr() + A_.nonZeros(), H.valuePtr());
      rotate_groups(H, motion);
    }
    const std::vector<char> eliminated_column = with_ghosts(eliminated);
    const auto set = [&](double& value, double to) {
      if (in_place && value != to) restore.changed.emplace_back(&value - H.valuePtr(), value);
      value = to;
    };
    for (int j = 0; j < H.outerSize(); ++j)
      for (SparseMatrix::InnerIterator e(H, j); e; ++e) {
        const bool ej = eliminated_column[static_cast<std::size_t>(j)], ei = eliminated[static_cast<std::size_t>(e.row())];
        if (ei || ej)
          set(e.valueRef(), e.row() == j ? 1.0 : 0.0);
        else if (e.row() == j && shift(j) != 0.0)
          set(e.valueRef(), e.valueRef() + shift(j));
      }
    return H;
  }

  // The engine's set-up for the Newton matrix H.
  FactorizationResult set_up_newton_matrix(KrylovSolver& krylov, const KrylovHints& hints, const Motions& motion,
                                           const std::vector<char>& eliminated, const SparseMatrix& H) const {
    KrylovHints system_hints(hints.near_null, hints.block_size);
    system_hints.rows = all_.size() > 1 ? &all_ : hints.rows;
    to_frame(system_hints.near_null, motion);
    for (Eigen::Index i = 0; i < H.rows() && system_hints.near_null.cols() > 0; ++i)
      if (eliminated[static_cast<std::size_t>(i)]) system_hints.near_null.row(i).setZero();
    return krylov.compute(H, system_hints);
  }

  // The Newton step: the held and pushed coordinates (and the tied rows) prescribed, the others
  // and every other unknown from (A + diag(w j''))_FF d_F = -grad_F - A_FE d_E by CG, to a
  // tolerance that follows the certificate's residual `worst`; with `clip` the negative
  // curvatures are left out.
  NewtonOutcome newton_step(KrylovSolver& krylov, const KrylovHints& hints, const Motions& motion,
                            const Eigen::VectorXd& r, bool clip, double worst, FullSpaceStatistics& st,
                            SystemCache& cache, Eigen::VectorXd* step) const {
    const Eigen::Index n = A_.rows();
    Eigen::VectorXd rhs = -r;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);  // in the groups' frames
    std::vector<char> eliminated(static_cast<std::size_t>(n), 0);
    for (int row : tied_) eliminated[static_cast<std::size_t>(row)] = 1;
    Eigen::VectorXd shift = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd frames(2 * static_cast<Eigen::Index>(groups_.size()));
    for (std::size_t k = 0; k < groups_.size(); ++k) {
      frames.segment<2>(2 * static_cast<Eigen::Index>(k)) = motion.group[k].e;
      group_unknowns(groups_[k], motion.group[k], clip, eliminated, d, rhs, shift);
    }
    for (std::size_t k = 0; k < coordinates_.size(); ++k) {
      const Motion& mk = motion.coordinate[k];
      const int row = coordinates_[k].row;
      if (coordinates_[k].group >= 0) continue;
      if (mk.held || mk.pushed) {
        eliminated[static_cast<std::size_t>(row)] = 1;
        d(row) = mk.held ? 0.0 : mk.step;
      } else {
        rhs(row) = -mk.grad;
        shift(row) = clip ? std::max(0.0, mk.curvature) : mk.curvature;
      }
    }
    // a semi-coercive problem's Newton matrix is singular along a free motion that no held unknown
    // and no law's curvature stops: there a proximal term on the moving coordinates (a Levenberg-
    // Marquardt shift, rho times the decade of the certificate's residual) keeps it definite and
    // vanishes as the iteration converges
    if (free_motions_ && !holds_free_motions(eliminated, shift)) {
      const double mu = proximal_ * std::pow(10.0, std::floor(std::log10(std::clamp(worst, 1e-16, 1.0))));
      for (const Coordinate& c : coordinates_)
        if (!eliminated[static_cast<std::size_t>(c.row)]) shift(c.row) += mu;
    }
    // the prescribed steps' forces on the others, in the groups' frames
    Eigen::VectorXd Ad = d;
    to_frame(Ad, motion, true);
    Ad = multiply(Ad);
    to_frame(Ad, motion);
    for (Eigen::Index i = 0; i < n; ++i) rhs(i) = eliminated[static_cast<std::size_t>(i)] ? d(i) : rhs(i) - Ad(i);
    auto tc = Clock::now();
    const bool same_system = all_.min(eliminated == cache.eliminated && shift == cache.shift && frames == cache.frames
                                          ? 1.0
                                          : 0.0) > 0.0;
    // The engine may read the matrix where it lies until the solve (hemivem/krylov_solver.hpp):
    // a Newton matrix written into the lent matrix stays there until the solve is done.
    const bool in_place = writes_in_place(krylov);
    RestoreValues restore(in_place ? lent_ : nullptr);
    const SparseMatrix* H = nullptr;
    if (in_place || !same_system) H = &write_newton_matrix(motion, eliminated, shift, in_place, cache, restore);
    if (!same_system) {
      const FactorizationResult set_up = set_up_newton_matrix(krylov, hints, motion, eliminated, *H);
      ++st.preconditioner_setups;
      st.preconditioner_seconds += since(tc);
      cache.eliminated.clear();
      cache.shift.resize(0);
      if (!set_up.ok())
        return {"the preconditioner of " + krylov.name() + " failed (" + to_string(set_up.status) + "): " +
                    set_up.message,
                set_up.status != FactorizationStatus::not_positive_definite};
      cache.eliminated = std::move(eliminated);
      cache.shift = std::move(shift);
      cache.frames = std::move(frames);
    }
    const double rtol = std::clamp(worst * worst, krylov_floor, krylov_cap);
    *step = d;
    tc = Clock::now();
    const KrylovSolveResult solved = krylov.solve(rhs, step, rtol, max_krylov_iterations);
    restore.restore();
    st.krylov_seconds += since(tc);
    st.krylov_iterations += solved.iterations;
    to_frame(*step, motion, true);
    if (all_.min(step->allFinite() ? 1.0 : 0.0) > 0.0 && (solved.ok() || (solved.status == FactorizationStatus::numerical_failure &&
                                              solved.relative_residual < 1.0)))
      return {};
    return {"the Newton system's solve by " + krylov.name() + " failed (" + to_string(solved.status) +
            "): " + solved.message};
  }

  void record(MinimizerResult& result, int it, double E, const Certificate& c, const Eigen::VectorXd& x,
              Clock::time_point t0) const {
    IterationRecord rec;
    rec.iteration = it;
    rec.objective = E;
    rec.primal = c.primal;
    rec.dual = c.dual;
    rec.active = static_cast<int>(all_.sum(count_at_bound(p_, coordinates_of(x))));
    rec.seconds = since(t0);
    result.history.push_back(rec);
  }

  // A group's two unknowns in its frame (e, t), rows row1 and row2: each prescribed (eliminated,
  // its step in d) or free with the right-hand side -grad and the law's curvature along it (its
  // negative part left out with `clip`): stuck, both held; leaving 0 along e, t held; held on a
  // kink in radius, e held; in its piece, both free; pinned onto a radius, e prescribed there
  // (onto 0: both, the step -v).
  static void group_unknowns(const Group& gr, const GroupMotion& g, bool clip, std::vector<char>& eliminated,
                             Eigen::VectorXd& d, Eigen::VectorXd& rhs, Eigen::VectorXd& shift) {
    using Mode = GroupMotion::Mode;
    const auto prescribe = [&](int row, double value) {
      eliminated[static_cast<std::size_t>(row)] = 1;
      d(row) = value;
    };
    const auto moves = [&](int row, const Eigen::Vector2d& u, double curvature) {
      rhs(row) = -g.grad.dot(u);
      shift(row) = std::min(clip ? std::max(0.0, curvature) : curvature,
                            max_group_curvature * gr.block.diagonal().maxCoeff());
    };
    const bool pinned = !std::isnan(g.pin);
    switch (g.mode) {
      case Mode::stuck:
        prescribe(gr.row1, 0.0);
        prescribe(gr.row2, 0.0);
        break;
      case Mode::ray:
        if (pinned)
          prescribe(gr.row1, g.pin);
        else
          moves(gr.row1, g.e, g.radial_curvature);
        prescribe(gr.row2, 0.0);
        break;
      case Mode::held:
        prescribe(gr.row1, 0.0);
        moves(gr.row2, g.t, g.tangential_curvature);
        break;
      case Mode::plane:
        if (!pinned) {
          moves(gr.row1, g.e, g.radial_curvature);
          moves(gr.row2, g.t, g.tangential_curvature);
        } else if (g.pin == 0.0) {
          prescribe(gr.row1, -g.r);
          prescribe(gr.row2, 0.0);
        } else {
          prescribe(gr.row1, g.pin - g.r);
          moves(gr.row2, g.t, g.tangential_curvature);
        }
        break;
    }
  }

  // Per coordinate: held on its knot, or moving within its piece box on the side of descent,
  // with the derivative and the curvature of E there; then the epsilon-active ones pushed onto
  // the knot they move against.
  Motions classify(const Eigen::VectorXd& x, const Eigen::VectorXd& r) const {
    Motions motions;
    std::vector<Motion>& motion = motions.coordinate;
    motion.resize(coordinates_.size());
    double eps = 0.0;
    for (std::size_t k = 0; k < coordinates_.size(); ++k) {
      const Coordinate& c = coordinates_[k];
      Motion& mk = motion[k];
      if (c.group >= 0) continue;
      const double a = x(c.row) - c.origin, g = r(c.row);
      const double up = g + c.w * c.law->derivative(LawPart::j, a, +1);
      const double down = g + c.w * c.law->derivative(LawPart::j, a, -1);
      int side = +1;
      if (c.on_knot(a)) {
        const bool rises = a < c.hi && up < 0.0, falls = a > c.lo && down > 0.0;
        if (!rises && !falls) {
          mk.held = true;
          mk.lo = mk.hi = a;
          continue;
        }
        side = rises && (!falls || -up >= down) ? +1 : -1;
        mk.lo = side > 0 ? a : c.knot_below(a);
        mk.hi = side > 0 ? c.knot_above(a) : a;
      } else {
        mk.lo = c.knot_below(a);
        mk.hi = c.knot_above(a);
      }
      mk.grad = side > 0 ? up : down;
      mk.curvature = c.w * c.law->second_derivative(LawPart::j, a, side);
      const double diag = stiffness_(static_cast<Eigen::Index>(k)) + std::max(0.0, mk.curvature);
      const double trial = diag > 0.0 ? std::clamp(a - mk.grad / diag, mk.lo, mk.hi) : a;
      eps = std::max(eps, std::abs(trial - a));
    }
    for (const Group& gr : groups_) {
      const Coordinate &c1 = coordinates_[static_cast<std::size_t>(gr.first)], &c2 = coordinates_[static_cast<std::size_t>(gr.second)];
      const GroupMotion& g = motions.group.emplace_back(
          group_motion(*c1.law, c1.w, Eigen::Vector2d(x(gr.row1) - c1.origin, x(gr.row2) - c2.origin),
                       Eigen::Vector2d(r(gr.row1), r(gr.row2)), gr.block));
      if (g.mode != GroupMotion::Mode::stuck)
        eps = std::max(eps, (group_trial(g, -g.grad / g.scale, 1.0) - g.v).norm());
    }
    eps = all_.max(eps);
    for (GroupMotion& g : motions.group) pin_group(g, eps);
    for (std::size_t k = 0; k < coordinates_.size(); ++k) {
      const Coordinate& c = coordinates_[k];
      Motion& mk = motion[k];
      if (mk.held || c.group >= 0) continue;
      const double a = x(c.row) - c.origin;
      if (mk.grad > 0.0 && std::isfinite(mk.lo) && a - mk.lo <= eps) {
        mk.pushed = true;
        mk.step = mk.lo - a;
      } else if (mk.grad < 0.0 && std::isfinite(mk.hi) && mk.hi - a <= eps) {
        mk.pushed = true;
        mk.step = mk.hi - a;
      }
    }
    return motions;
  }

  // The groups' rows and blocks, and where their pairs of entries lie in A's values.
  void find_groups() {
    if (p_.groups.empty()) return;
    if (!A_.isCompressed()) throw InternalError("the full-space route needs a compressed matrix");
    std::vector<int> group_of_row(static_cast<std::size_t>(A_.rows()), -1);
    for (const CoordinateGroup& cg : p_.groups) {
      Group g;
      g.first = static_cast<int>(cg.first);
      g.second = static_cast<int>(cg.second);
      g.row1 = coordinates_[static_cast<std::size_t>(g.first)].row;
      g.row2 = coordinates_[static_cast<std::size_t>(g.second)].row;
      g.block << A_.coeff(g.row1, g.row1), A_.coeff(g.row1, g.row2), A_.coeff(g.row2, g.row1), A_.coeff(g.row2, g.row2);
      coordinates_[static_cast<std::size_t>(g.first)].group = coordinates_[static_cast<std::size_t>(g.second)].group =
          static_cast<int>(groups_.size());
      group_of_row[static_cast<std::size_t>(g.row1)] = group_of_row[static_cast<std::size_t>(g.row2)] =
          static_cast<int>(groups_.size());
      groups_.push_back(std::move(g));
    }
    const int* outer = A_.outerIndexPtr();
    const int* inner = A_.innerIndexPtr();
    std::vector<Eigen::Index> at1(groups_.size(), -1), at2(groups_.size(), -1);
    for (Eigen::Index j = 0; j < A_.outerSize(); ++j) {
      for (Eigen::Index i = outer[j]; i < outer[j + 1]; ++i)
        if (const int g = group_of_row[static_cast<std::size_t>(inner[i])]; g >= 0)
          (inner[i] == groups_[static_cast<std::size_t>(g)].row1 ? at1 : at2)[static_cast<std::size_t>(g)] = i;
      for (Eigen::Index i = outer[j]; i < outer[j + 1]; ++i) {
        const int k = group_of_row[static_cast<std::size_t>(inner[i])];
        if (k < 0) continue;
        const auto g = static_cast<std::size_t>(k);
        if (at1[g] < 0 && at2[g] < 0) continue;  // the group's pair in this column already taken
        if (at1[g] < 0 || at2[g] < 0) throw InternalError("a group's two rows do not share their pattern");
        groups_[g].in_columns.emplace_back(at1[g], at2[g]);
        at1[g] = at2[g] = -1;
      }
    }
    // the group's two columns in this process's rows (all of them in one process)
    for (Group& g : groups_) g.columns = column_pairs(g.row1, g.row2);
  }

  // The places in A's values of the entries of columns c1 and c2 in the same row, pair by pair;
  // InternalError when the two columns do not share their pattern.
  std::vector<std::pair<Eigen::Index, Eigen::Index>> column_pairs(Eigen::Index c1, Eigen::Index c2) const {
    const int* outer = A_.outerIndexPtr();
    const int* inner = A_.innerIndexPtr();
    const Eigen::Index n1 = outer[c1 + 1] - outer[c1];
    if (n1 != outer[c2 + 1] - outer[c2]) throw InternalError("a group's two columns do not share their pattern");
    std::vector<std::pair<Eigen::Index, Eigen::Index>> pairs;
    for (Eigen::Index q = 0; q < n1; ++q) {
      if (inner[outer[c1] + q] != inner[outer[c2] + q])
        throw InternalError("a group's two columns do not share their pattern");
      pairs.emplace_back(outer[c1] + q, outer[c2] + q);
    }
    return pairs;
  }

  // The groups of other processes whose two unknowns are ghost columns here (a node's unknowns
  // are read together): each owner sends, at a group's first unknown, the global number of its
  // second, and where the pairs of entries of the two columns lie in A's values.
  void find_ghost_groups() {
    const RowLayout& layout = all_.layout();
    Eigen::VectorXd partner = Eigen::VectorXd::Zero(A_.cols());
    for (const Group& g : groups_) partner(g.row1) = static_cast<double>(layout.first + g.row2 + 1);
    all_.update_ghosts(partner);
    for (Eigen::Index c1 = layout.owned; c1 < A_.cols(); ++c1) {
      if (partner(c1) == 0.0) continue;
      // the ghosts increase (RowLayout): the second unknown's local column by bisection
      const auto second = static_cast<Eigen::Index>(partner(c1)) - 1;
      const auto found = std::lower_bound(layout.ghosts.begin(), layout.ghosts.end(), second);
      if (found == layout.ghosts.end() || *found != second)
        throw InternalError("a group's second unknown is not read with its first");
      GhostGroup g;
      g.column1 = c1;
      g.column2 = layout.owned + (found - layout.ghosts.begin());
      g.columns = column_pairs(g.column1, g.column2);
      ghost_groups_.push_back(std::move(g));
    }
  }

  // The rows of every group's two unknowns in the frame (e, t) of its motion (to_frame), or back
  // (from_frame): the Newton system is solved in that frame, where a group's constrained
  // directions are single unknowns.
  template <class M>
  void to_frame(M& m, const Motions& motions, bool back = false) const {
    for (std::size_t k = 0; k < groups_.size(); ++k) {
      const GroupMotion& g = motions.group[k];
      const Eigen::Vector2d e = g.e, t = g.t;
      for (Eigen::Index c = 0; c < m.cols(); ++c) {
        const double a = m(groups_[k].row1, c), b = m(groups_[k].row2, c);
        m(groups_[k].row1, c) = back ? e(0) * a + t(0) * b : e(0) * a + e(1) * b;
        m(groups_[k].row2, c) = back ? e(1) * a + t(1) * b : t(0) * a + t(1) * b;
      }
    }
  }
  // H's values R^T H R for each group's rotation R = [e t] (H has A's storage); on several
  // processes also the ghost columns of other processes' groups, whose frames their owners send
  // (collective where any process has a group).
  void rotate_groups(SparseMatrix& H, const Motions& motions) const {
    double* v = H.valuePtr();
    const auto rotate = [v](const Eigen::Vector2d& e, const Eigen::Vector2d& t,
                            const std::vector<std::pair<Eigen::Index, Eigen::Index>>& pairs) {
      for (const auto& [i, j] : pairs) {
        const double a = v[i], b = v[j];
        v[i] = e(0) * a + e(1) * b;
        v[j] = t(0) * a + t(1) * b;
      }
    };
    for (std::size_t k = 0; k < groups_.size(); ++k) {
      const Eigen::Vector2d e = motions.group[k].e, t = motions.group[k].t;
      rotate(e, t, groups_[k].in_columns);
      rotate(e, t, groups_[k].columns);
    }
    if (all_.size() == 1 || !any_groups_) return;
    Eigen::VectorXd frames = Eigen::VectorXd::Zero(A_.cols());
    for (std::size_t k = 0; k < groups_.size(); ++k) {
      frames(groups_[k].row1) = motions.group[k].e(0);
      frames(groups_[k].row2) = motions.group[k].e(1);
    }
    all_.update_ghosts(frames);
    for (const GhostGroup& g : ghost_groups_) {
      const Eigen::Vector2d e(frames(g.column1), frames(g.column2));
      rotate(e, Eigen::Vector2d(-e(1), e(0)), g.columns);  // t: e turned a quarter (group_motion.hpp)
    }
  }

  const ReducedProblem& p_;
  const SparseMatrix& A_;  ///< the owned rows, local columns (hemivem/row_distribution.hpp)
  SparseMatrix* lent_;     ///< A_ itself where the Newton systems may be written into it, or null
  const Eigen::VectorXd& b_;
  const RowDistribution& all_;
  double tol_;
  std::vector<Coordinate> coordinates_;
  Eigen::VectorXd stiffness_, load_;
  std::vector<char> is_coordinate_;  // 1: a coordinate's row, 2: a tied row
  std::vector<int> tied_;
  std::vector<Group> groups_;
  /// The ghost columns of another process's group and the pairs of entries of the two columns.
  struct GhostGroup {
    Eigen::Index column1 = 0, column2 = 0;
    std::vector<std::pair<Eigen::Index, Eigen::Index>> columns;
  };
  std::vector<GhostGroup> ghost_groups_;
  bool any_groups_ = false;  ///< some process has a group (the same on every process)
  /// A semi-coercive problem's free motions (this process's rows), or null; the largest stiffness
  /// of a coordinate over the processes, the scale of the proximal term of its Newton systems.
  const Eigen::MatrixXd* free_motions_ = nullptr;
  const std::vector<Eigen::Index>* numbers_ = nullptr;  ///< as ShareView::numbers
  double proximal_ = 0.0;

  /// Collective: the sum over the processes of each process's `mine` (of one size on all), the
  /// same bits on each.
  Eigen::MatrixXd summed(const Eigen::MatrixXd& mine) const {
    if (all_.size() == 1) return mine;
    const Eigen::VectorXd sum = all_.sum_in_rank_order(mine.reshaped());
    return sum.reshaped(mine.rows(), mine.cols());
  }

  // Does the Newton matrix of the unknowns `eliminated` and the curvature shifts `shift` hold every
  // free motion M xi, within 1e-8 of the stiffness rho? On a free motion it is the quadratic form
  // xi^T K xi, K = sum over the coordinates' and tied rows of weight_i M_i^T M_i, the weight rho at
  // an eliminated row and the shift at a moving one (a group's rows the smaller of its two).
  bool holds_free_motions(const std::vector<char>& eliminated, const Eigen::VectorXd& shift) const {
    const Eigen::MatrixXd& M = *free_motions_;
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(M.cols(), M.cols()), G = K;
    const auto weight = [&](int row) { return eliminated[static_cast<std::size_t>(row)] ? proximal_ : std::max(0.0, shift(row)); };
    const auto add = [&](int row, double w) {
      const Eigen::MatrixXd mm = M.row(row).transpose() * M.row(row);
      K += w * mm;
      G += mm;
    };
    for (const Coordinate& c : coordinates_) {
      if (c.group >= 0) continue;
      add(c.row, weight(c.row));
    }
    for (const Group& g : groups_) {
      const double w = std::min(weight(g.row1), weight(g.row2));
      add(g.row1, w);
      add(g.row2, w);
    }
    for (int row : tied_) add(row, proximal_);
    K = summed(K);
    G = summed(G);
    const double top = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(G, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    const double least = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
    return all_.min(least > 1e-8 * proximal_ * top ? 1.0 : 0.0) > 0.0;  // every process decides alike
  }

  // Is E bounded below along the free motions? check_existence() of the coordinates whose null
  // directions are the motions' coordinate components (those that keep the tied unknowns at 0),
  // orthonormalised, with the load's work along each as c's: along a free motion A's energy is
  // constant and E changes by the laws' and the load's terms alone. Collective: the whole
  // problem's coordinates and the motions' components there are gathered on every process, which
  // each decides alike.
  Existence existence() const {
    Eigen::MatrixXd M = *free_motions_;
    if (all_.max(tied_.empty() ? 0.0 : 1.0) > 0.0) {
      Eigen::MatrixXd TT = Eigen::MatrixXd::Zero(M.cols(), M.cols());
      for (int row : tied_) TT += M.row(row).transpose() * M.row(row);
      M = M * null_space(summed(TT));
    }
    const Eigen::VectorXd work = summed(M.transpose() * b_);
    // per coordinate: its number, its group's other coordinate (-1: none), law, weight, bounds and
    // the motions' components
    const Eigen::Index per = 6 + M.cols(), m = p_.size();
    const auto number = [&](Eigen::Index k) { return numbers_ ? (*numbers_)[static_cast<std::size_t>(k)] : k; };
    Eigen::VectorXd partner = Eigen::VectorXd::Constant(m, -1.0);
    for (const CoordinateGroup& g : p_.groups) {
      partner(g.first) = static_cast<double>(number(g.second));
      partner(g.second) = static_cast<double>(number(g.first));
    }
    Eigen::VectorXd sent(per * m);
    for (Eigen::Index k = 0; k < m; ++k) {
      sent.segment(per * k, 6) << static_cast<double>(number(k)), partner(k), p_.law_index(k), p_.w(k), p_.lower(k),
          p_.upper(k);
      sent.segment(per * k + 6, M.cols()) = M.row(coordinates_[static_cast<std::size_t>(k)].row).transpose();
    }
    const Eigen::VectorXd all = all_.all_gather(sent);
    const Eigen::Index count = all.size() / per;
    ReducedProblem q;
    q.laws = p_.laws;
    q.w.resize(count);
    q.law_index.resize(count);
    q.lo.resize(count);
    q.hi.resize(count);
    Eigen::MatrixXd D(count, M.cols());
    std::vector<char> seen(static_cast<std::size_t>(count), 0);
    for (Eigen::Index at = 0; at < all.size(); at += per) {
      const auto k = static_cast<Eigen::Index>(all(at));
      if (k < 0 || k >= count || seen[static_cast<std::size_t>(k)])
        throw InternalError("the processes' coordinates are not the whole problem's, each once");
      seen[static_cast<std::size_t>(k)] = 1;
      const auto other = static_cast<Eigen::Index>(all(at + 1));
      if (other > k) q.groups.push_back({k, other});
      q.law_index(k) = static_cast<int>(all(at + 2));
      q.w(k) = all(at + 3);
      q.lo(k) = all(at + 4);
      q.hi(k) = all(at + 5);
      D.row(k) = all.segment(at + 6, M.cols()).transpose();
    }
    std::sort(q.groups.begin(), q.groups.end(),
              [](const CoordinateGroup& a, const CoordinateGroup& b) { return a.first < b.first; });
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(D, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    Eigen::Index r = 0;
    while (r < sigma.size() && sigma(r) > null_space_tolerance * sigma(0)) ++r;
    q.c = svd.matrixU().leftCols(r) *
          (svd.matrixV().leftCols(r).transpose() * work).cwiseQuotient(sigma.head(r));
    return check_existence(q, svd.matrixU().leftCols(r));
  }
};

}  // namespace

CertifiedPoint certify_full_space(const Condensation& posed, const Eigen::VectorXd& x, double tol) {
  check_tolerance(tol, "tolerance");
  const OneProcessRows alone(posed.rotated_matrix().rows());
  return FullSpaceNewton(whole(posed, posed.reduced(), posed.origin()), alone, tol).certify(x);
}

MinimizerResult minimize_full_space(const Condensation& posed, KrylovSolver& krylov, const KrylovHints& hints,
                                    const MinimizerOptions& options, Eigen::VectorXd* x,
                                    FullSpaceStatistics* statistics) {
  return minimize_full_space(posed, posed.reduced(), posed.origin(), krylov, hints, options, x, statistics);
}

namespace {
const Eigen::MatrixXd* motions_of(const FullSpaceShare& share) {
  return share.free_motions.cols() > 0 ? &share.free_motions : nullptr;
}
}  // namespace

CertifiedPoint certify_full_space(const FullSpaceShare& share, const RowDistribution& rows, const Eigen::VectorXd& x,
                                  double tol) {
  check_tolerance(tol, "tolerance");
  const ShareView view{share.matrix,          share.load,   share.coordinates,
                       share.coordinate_rows, share.origin, share.tied_rows, nullptr, motions_of(share), &share.coordinate_numbers};
  return FullSpaceNewton(view, rows, tol).certify(x);
}

namespace {

MinimizerResult run_newton(const ShareView& view, KrylovSolver& krylov, const KrylovHints& hints,
                           const MinimizerOptions& options, Eigen::VectorXd* x, FullSpaceStatistics* statistics) {
  if (!x) throw InternalError("minimize_full_space needs a point to start from and return");
  if (std::string why; !options.is_valid(&why)) throw InputError(why, "MinimizerOptions");
  const OneProcessRows alone(view.A.rows());
  const RowDistribution& all = hints.rows ? *hints.rows : alone;
  return FullSpaceNewton(view, all, options.tolerance).run(krylov, hints, options, x, statistics);
}

}  // namespace

MinimizerResult minimize_full_space(const Condensation& posed, const ReducedProblem& coordinates,
                                    const Eigen::VectorXd& origin, KrylovSolver& krylov, const KrylovHints& hints,
                                    const MinimizerOptions& options, Eigen::VectorXd* x,
                                    FullSpaceStatistics* statistics) {
  if (origin.size() != coordinates.size())
    throw InternalError("the full-space route needs an origin for each coordinate");
  return run_newton(whole(posed, coordinates, origin), krylov, hints, options, x, statistics);
}

RowLayout layout_of(const Condensation& posed, Eigen::Index first, Eigen::Index owned) {
  const SparseMatrix& A = posed.rotated_matrix();
  if (first < 0 || owned < 0 || first + owned > A.rows()) throw InternalError("rows outside the posed problem");
  RowLayout layout;
  layout.first = first;
  layout.owned = owned;
  layout.global = A.rows();
  std::vector<char> read(static_cast<std::size_t>(A.rows()), 0);
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)  // A is symmetric: column j's rows are row j's columns
    if (j < first || j >= first + owned)
      for (SparseMatrix::InnerIterator e(A, j); e; ++e)
        if (e.row() >= first && e.row() < first + owned) {
          read[static_cast<std::size_t>(j)] = 1;
          break;
        }
  for (Eigen::Index j = 0; j < A.rows(); ++j)
    if (read[static_cast<std::size_t>(j)]) layout.ghosts.push_back(j);
  return layout;
}

void share_coordinates(const Condensation& posed, Eigen::Index first, Eigen::Index owned, FullSpaceShare& share) {
  const ReducedProblem& p = posed.reduced();
  const auto mine = [&](int row) { return row >= first && row < first + owned; };
  std::vector<Eigen::Index> in_share(static_cast<std::size_t>(p.size()), -1);
  for (Eigen::Index k = 0; k < p.size(); ++k)
    if (mine(posed.rotated_index(k))) {
      in_share[static_cast<std::size_t>(k)] = static_cast<Eigen::Index>(share.coordinate_numbers.size());
      share.coordinate_numbers.push_back(k);
      share.coordinate_rows.push_back(posed.rotated_index(k) - static_cast<int>(first));
    }
  set_share_coordinates(p, posed.origin(), share);
  for (const CoordinateGroup& g : p.groups) {
    const Eigen::Index a = in_share[static_cast<std::size_t>(g.first)], b = in_share[static_cast<std::size_t>(g.second)];
    if ((a < 0) != (b < 0)) throw InternalError("a share that splits a group's two unknowns");
    if (a >= 0) share.coordinates.groups.push_back({a, b});
  }
  for (int row : posed.tied_rows())
    if (mine(row)) share.tied_rows.push_back(row - static_cast<int>(first));
}

void set_share_coordinates(const ReducedProblem& p, const Eigen::VectorXd& origin, FullSpaceShare& share) {
  if (origin.size() != p.size()) throw InternalError("the full-space route needs an origin for each coordinate");
  const auto m = static_cast<Eigen::Index>(share.coordinate_numbers.size());
  ReducedProblem& q = share.coordinates;
  q.laws = p.laws;
  q.c = Eigen::VectorXd::Zero(m);
  q.w.resize(m);
  q.law_index.resize(m);
  q.lo.resize(m);
  q.hi.resize(m);
  share.origin.resize(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index k = share.coordinate_numbers[static_cast<std::size_t>(i)];
    if (k < 0 || k >= p.size()) throw InternalError("a share's coordinate outside the whole problem's");
    q.w(i) = p.w(k);
    q.law_index(i) = p.law_index(k);
    q.lo(i) = p.lower(k);
    q.hi(i) = p.upper(k);
    share.origin(i) = origin(k);
  }
}

FullSpaceShare share_of(const Condensation& posed, const RowLayout& layout) {
  const SparseMatrix& A = posed.rotated_matrix();
  if (layout.global != A.rows() || layout.first < 0 || layout.first + layout.owned > A.rows())
    throw InternalError("a layout of another problem's rows");
  const Eigen::Index first = layout.first, owned = layout.owned;
  // local column of each global one read
  std::vector<int> local(static_cast<std::size_t>(A.rows()), -1);
  for (Eigen::Index i = 0; i < owned; ++i) local[static_cast<std::size_t>(first + i)] = static_cast<int>(i);
  for (std::size_t g = 0; g < layout.ghosts.size(); ++g)
    local[static_cast<std::size_t>(layout.ghosts[g])] = static_cast<int>(owned + static_cast<Eigen::Index>(g));
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(A, j); e; ++e)
      if (e.row() >= first && e.row() < first + owned) {
        const int c = local[static_cast<std::size_t>(j)];
        if (c < 0) throw InternalError("a layout whose ghosts miss a column its rows read");
        entries.emplace_back(static_cast<int>(e.row() - first), c, e.value());
      }
  FullSpaceShare share;
  share.matrix.resize(owned, owned + static_cast<Eigen::Index>(layout.ghosts.size()));
  share.matrix.setFromTriplets(entries.begin(), entries.end());
  share.matrix.makeCompressed();
  share.load = posed.rotated_load().segment(first, owned);
  share_coordinates(posed, first, owned, share);
  if (posed.free_motions().cols() > 0) share.free_motions = posed.free_motions().middleRows(first, owned);
  return share;
}

MinimizerResult minimize_full_space(const FullSpaceShare& share, KrylovSolver& krylov, const KrylovHints& hints,
                                    const MinimizerOptions& options, Eigen::VectorXd* x,
                                    FullSpaceStatistics* statistics) {
  const ShareView view{share.matrix,          share.load,   share.coordinates,
                       share.coordinate_rows, share.origin, share.tied_rows, nullptr, motions_of(share), &share.coordinate_numbers};
  return run_newton(view, krylov, hints, options, x, statistics);
}

MinimizerResult minimize_full_space_in_place(FullSpaceShare& share, KrylovSolver& krylov, const KrylovHints& hints,
                                             const MinimizerOptions& options, Eigen::VectorXd* x,
                                             FullSpaceStatistics* statistics) {
  const ShareView view{share.matrix, share.load,   share.coordinates, share.coordinate_rows,
                       share.origin, share.tied_rows, &share.matrix, motions_of(share), &share.coordinate_numbers};
  return run_newton(view, krylov, hints, options, x, statistics);
}

}  // namespace hemivem
