// The DC algorithm with a proximal bundle method for the convex subproblems (README.md).
#include <hemivem/bundle_dca_minimizer.hpp>

#include <hemivem/error.hpp>
#include <hemivem/minimizer_run.hpp>

#include <Eigen/Cholesky>
#include <Eigen/LU>
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

// ---- groups of coordinates: the bundle subproblem with models of a pair --------------------
//
// A group's term phi_G(v) = w j1(|v|) is a convex function of the pair v = (a_first, a_second)
// and is modelled as one: psi_G(v) = max_l (b_l + s_l . v), the linearisations of phi_G in the
// plane (s = w j1'(r) v / r at r = |v| > 0, any s in the disc of radius w j1'(0+) at v = 0;
// b = w j1(r) - w j1'(r) r is computed in one dimension, so that the cuts of a law that is
// linear in r, such as Tresca's, pass through the origin exactly). The subproblem
//
//   min 1/2 a^T H a - q^T a + sum_i psi_i(a_i) + sum_G psi_G(a_G)
//
// is solved by exact block minimisation (every coordinate on its own and every group as a
// pair, the others fixed) and, on the face the blocks identify, one Newton step on the face:
// a block's minimiser of a polyhedral model is the minimiser of the model on one of its faces
// (a piece or a node of psi_i, a bound; a cell, an edge or a vertex of psi_G), so the
// candidates are enumerated and the lowest value taken. A vertex is the intersection of cut
// planes, so a stuck group whose cuts meet at the origin is placed there exactly.

struct PlaneCut {
  double b = 0.0;
  Eigen::Vector2d s = Eigen::Vector2d::Zero();
  double at(const Eigen::Vector2d& v) const { return b + s.dot(v); }
};

double plane_model(const std::vector<PlaneCut>& cuts, const Eigen::Vector2d& v) {
  double m = -kInf;
  for (const PlaneCut& c : cuts) m = std::max(m, c.at(v));
  return m;
}

double line_model(const std::vector<Cut>& cuts, double t) {
  double m = -kInf;
  for (const Cut& c : cuts) m = std::max(m, c.at(t));
  return m;
}

// The face of one block at its minimiser: the free dimensions left on it (scalar: 1 on a piece,
// 0 at a node or bound; group: 2 in a cell, 1 on an edge, 0 at a vertex), the active cuts and,
// on a piece, cell or edge, the slope of the model there; on an edge its direction.
struct BlockFace {
  int free_dims = 0;
  std::vector<int> active;
  Eigen::Vector2d slope = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::Zero();
};

// min_t 1/2 h t^2 - r t + psi(t) over [lo, hi]: among the stationary points of the pieces, the
// breakpoints of the cuts and the bounds (each clamped into [lo, hi]), the lowest value.
double solve_scalar_block(double h, double r, const std::vector<Cut>& cuts, double lo, double hi, BlockFace& face) {
  auto value = [&](double t) { return 0.5 * h * t * t - r * t + line_model(cuts, t); };
  double best = 0.0, best_value = kInf;
  auto consider = [&](double t, int free_dims, std::vector<int> active) {
    const double clamped = std::min(std::max(t, lo), hi);
    if (clamped != t) free_dims = 0, active.clear();
    const double v = value(clamped);
    if (v < best_value) {
      best_value = v;
      best = clamped;
      face.free_dims = free_dims;
      face.active = std::move(active);
    }
  };
  for (double b : {lo, hi})
    if (std::isfinite(b)) consider(b, 0, {});
  const int m = static_cast<int>(cuts.size());
  for (int k = 0; k < m; ++k)
    for (int l = 0; l < m; ++l)
      if (cuts[static_cast<std::size_t>(k)].slope < cuts[static_cast<std::size_t>(l)].slope)
        consider(intersection(cuts[static_cast<std::size_t>(k)], cuts[static_cast<std::size_t>(l)]), 0, {k, l});
  for (int k = 0; k < m; ++k) consider((r - cuts[static_cast<std::size_t>(k)].slope) / h, 1, {k});
  if (face.free_dims == 1) face.slope(0) = cuts[static_cast<std::size_t>(face.active.front())].slope;
  return best;
}

// min_v 1/2 v^T A v - r^T v + psi_G(v): among the vertices, the minimisers on the edge lines and
// the stationary points of the cells, the lowest value (vertices first: the most constrained
// wins a tie).
Eigen::Vector2d solve_group_block(const Eigen::Matrix2d& A, const Eigen::Vector2d& r, const std::vector<PlaneCut>& cuts,
                                  BlockFace& face) {
  const Eigen::Matrix2d Ainv = A.inverse();
  auto value = [&](const Eigen::Vector2d& v) { return 0.5 * v.dot(A * v) - r.dot(v) + plane_model(cuts, v); };
  Eigen::Vector2d best = Eigen::Vector2d::Zero();
  double best_value = kInf;
  auto consider = [&](const Eigen::Vector2d& v, int free_dims, std::vector<int> active, const Eigen::Vector2d& direction) {
    if (!v.allFinite()) return;
    const double f = value(v);
    if (f < best_value) {
      best_value = f;
      best = v;
      face.free_dims = free_dims;
      face.active = std::move(active);
      face.direction = direction;
    }
  };
  const int m = static_cast<int>(cuts.size());
  auto cut = [&](int k) -> const PlaneCut& { return cuts[static_cast<std::size_t>(k)]; };
  auto distinct = [](const Eigen::Vector2d& d, const Eigen::Vector2d& s) {
    return d.norm() > 64.0 * std::numeric_limits<double>::epsilon() * s.norm();
  };
  for (int k = 0; k < m; ++k)
    for (int l = k + 1; l < m; ++l) {
      const Eigen::Vector2d d1 = cut(k).s - cut(l).s;
      if (!distinct(d1, cut(k).s.cwiseAbs() + cut(l).s.cwiseAbs())) continue;
      for (int o = l + 1; o < m; ++o) {
        const Eigen::Vector2d d2 = cut(k).s - cut(o).s;
        Eigen::Matrix2d M;
        M << d1(0), d1(1), d2(0), d2(1);
        const double det = M.determinant();
        if (!(std::abs(det) > 64.0 * std::numeric_limits<double>::epsilon() * d1.norm() * d2.norm())) continue;
        const Eigen::Vector2d rhs(cut(l).b - cut(k).b, cut(o).b - cut(k).b);
        consider(M.inverse() * rhs, 0, {k, l, o}, Eigen::Vector2d::Zero());
      }
    }
  for (int k = 0; k < m; ++k)
    for (int l = k + 1; l < m; ++l) {
      // min 1/2 v^T A v - r^T v + b_k + s_k . v on the line d . v = beta, d = s_k - s_l, as
      // v = v0 + t u. Two cuts of one intercept and slopes of one length (the cuts of a law
      // linear in r at two directions) meet on the line through the origin along s_k + s_l,
      // which is exact where the difference of nearby slopes would lose its digits.
      const Eigen::Vector2d d = cut(k).s - cut(l).s;
      if (!distinct(d, cut(k).s.cwiseAbs() + cut(l).s.cwiseAbs())) continue;
      Eigen::Vector2d v0 = Eigen::Vector2d::Zero(), u = Eigen::Vector2d(-d(1), d(0)).normalized();
      if (cut(k).b == cut(l).b) {
        const Eigen::Vector2d sum = cut(k).s + cut(l).s;
        if (cut(k).s.norm() == cut(l).s.norm() && sum.norm() > 0.0) u = sum.normalized();
      } else {
        v0 = d * ((cut(l).b - cut(k).b) / d.squaredNorm());
      }
      const double t = (r - A * v0 - cut(k).s).dot(u) / u.dot(A * u);
      consider(v0 + t * u, 1, {k, l}, u);
    }
  for (int k = 0; k < m; ++k) consider(Ainv * (r - cut(k).s), 2, {k}, Eigen::Vector2d::Zero());
  if (face.free_dims >= 1) face.slope = cut(face.active.front()).s;
  return best;
}

// The face the blocks' solutions lie on: the directions in which each stays on its face (a
// coordinate off its kinks and bounds; a group's plane, or the line of its one free direction)
// as `columns`, and the model's slope there.
void face_basis(const ReducedProblem& p, const Eigen::VectorXi& group_of, const std::vector<BlockFace>& faces,
                std::vector<Eigen::VectorXd>& columns, Eigen::VectorXd& slope) {
  const Eigen::Index n = slope.size();
  const auto U = [](Eigen::Index i) { return static_cast<std::size_t>(i); };
  for (Eigen::Index i = 0; i < n; ++i) {
    if (group_of(i) >= 0 || faces[U(i)].free_dims == 0) continue;
    columns.push_back(Eigen::VectorXd::Unit(n, i));
    slope(i) = faces[U(i)].slope(0);
  }
  for (const CoordinateGroup& g : p.groups) {
    const BlockFace& face = faces[U(g.first)];
    if (face.free_dims == 0) continue;
    slope(g.first) = face.slope(0);
    slope(g.second) = face.slope(1);
    if (face.free_dims == 2) {
      columns.push_back(Eigen::VectorXd::Unit(n, g.first));
      columns.push_back(Eigen::VectorXd::Unit(n, g.second));
    } else {
      Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
      c(g.first) = face.direction(0);
      c(g.second) = face.direction(1);
      columns.push_back(c);
    }
  }
}

// The bundle subproblem of a problem with groups; false when a diagonal block of H or H on a
// face is not positive definite. `faces` (one per coordinate, the group's at its first) keeps
// the faces of the solution (the active cuts, for the compression of the bundle).
bool solve_group_qp(const ReducedProblem& p, const Eigen::VectorXi& group_of, const Eigen::MatrixXd& H,
                    const Eigen::VectorXd& q, const std::vector<std::vector<Cut>>& cuts,
                    const std::vector<std::vector<PlaneCut>>& plane_cuts, Eigen::VectorXd& a,
                    std::vector<BlockFace>& faces, QpStats& stats) {
  const Eigen::Index n = a.size();
  const auto U = [](Eigen::Index i) { return static_cast<std::size_t>(i); };
  faces.assign(U(n), BlockFace{});
  a = p.project(a);
  auto model = [&](const Eigen::VectorXd& x) {
    double v = 0.5 * x.dot(H * x) - q.dot(x);
    for (Eigen::Index i = 0; i < n; ++i)
      if (group_of(i) < 0) v += line_model(cuts[U(i)], x(i));
    for (std::size_t g = 0; g < p.groups.size(); ++g)
      v += plane_model(plane_cuts[g], Eigen::Vector2d(x(p.groups[g].first), x(p.groups[g].second)));
    return v;
  };
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(H(i, i) > 0.0)) return false;
  for (const CoordinateGroup& g : p.groups)
    if (!(H(g.first, g.first) * H(g.second, g.second) > H(g.first, g.second) * H(g.second, g.first))) return false;
  double current = model(a);
  const int max_sweeps = 100 + 10 * static_cast<int>(n);
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    ++stats.steps;
    const Eigen::VectorXd before = a;
    // one sweep of exact block minimisation
    for (Eigen::Index i = 0; i < n; ++i) {
      if (group_of(i) >= 0) continue;
      const double r = q(i) - H.row(i).dot(a) + H(i, i) * a(i);
      a(i) = solve_scalar_block(H(i, i), r, cuts[U(i)], p.lower(i), p.upper(i), faces[U(i)]);
    }
    for (std::size_t k = 0; k < p.groups.size(); ++k) {
      const Eigen::Index f = p.groups[k].first, s = p.groups[k].second;
      Eigen::Matrix2d A;
      A << H(f, f), H(f, s), H(s, f), H(s, s);
      const Eigen::Vector2d v(a(f), a(s));
      const Eigen::Vector2d r = Eigen::Vector2d(q(f) - H.row(f).dot(a), q(s) - H.row(s).dot(a)) + A * v;
      const Eigen::Vector2d x = solve_group_block(A, r, plane_cuts[k], faces[U(f)]);
      a(f) = x(0);
      a(s) = x(1);
    }
    // one Newton step on the face of the blocks: a = a0 + N z, the model linear there
    std::vector<Eigen::VectorXd> columns;
    Eigen::VectorXd slope = Eigen::VectorXd::Zero(n);
    face_basis(p, group_of, faces, columns, slope);
    double after_sweep = model(a);
    if (!columns.empty()) {
      Eigen::MatrixXd N(n, static_cast<Eigen::Index>(columns.size()));
      for (std::size_t c = 0; c < columns.size(); ++c) N.col(static_cast<Eigen::Index>(c)) = columns[c];
      const Eigen::LLT<Eigen::MatrixXd> llt(N.transpose() * H * N);
      if (llt.info() != Eigen::Success) return false;
      const Eigen::VectorXd z = llt.solve(N.transpose() * (q - slope - H * a));
      if (z.allFinite()) {
        const Eigen::VectorXd newton = a + N * z;
        const double m = model(newton);
        bool inside = true;
        for (Eigen::Index i = 0; i < n; ++i) inside = inside && newton(i) >= p.lower(i) && newton(i) <= p.upper(i);
        if (inside && m <= after_sweep) a = newton, after_sweep = m;
      }
    }
    if (after_sweep > current) {  // rounding: the point before the sweep is no worse
      a = before;
      break;
    }
    const bool lower = after_sweep < current;
    current = after_sweep;
    if (!lower || (a - before).cwiseAbs().maxCoeff() <= 1e-15 * a.cwiseAbs().maxCoeff()) break;
  }
  return true;
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
      : run_(run), p_(run.problem()), o_(options), n_(p_.size()), cuts_(U(n_)), added_(U(n_), 0),
        group_of_(p_.group_of()), plane_cuts_(p_.groups.size()), plane_added_(p_.groups.size(), 0) {
    mu_ = o_.proximal_weight * p_.S.diagonal().cwiseAbs().maxCoeff();
    H_ = p_.S;
    H_.diagonal().array() += mu_;
  }

  // The cuts of phi_i(t) = w_i j1(t) at a (and of phi_G(v) = w j1(|v|) per group, where y, the
  // linearisation of F2, gives the residual of the subproblem): one subgradient evaluation of F1.
  void add_cuts(const Eigen::VectorXd& a, const Eigen::VectorXd& y) {
    run_.count_subgradients();
    if (!p_.groups.empty()) add_plane_cuts(a, y);
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (group_of_(i) >= 0) continue;
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
      std::vector<Envelope> env;
      QpStats qs;
      if (p_.groups.empty()) {
        env.resize(U(n_));
        for (Eigen::Index i = 0; i < n_; ++i) env[U(i)] = envelope(cuts_[U(i)], p_.lower(i), p_.upper(i));
        if (!solve_qp(H_, cy + mu_ * center, cuts_, env, trial, state_, qs)) {
          end.qp_failed = true;
          break;
        }
      } else if (!solve_group_qp(p_, group_of_, H_, cy + mu_ * center, cuts_, plane_cuts_, trial, faces_, qs)) {
        end.qp_failed = true;
        break;
      }
      qp_steps += qs.steps;
      double quad = 0.0;
      const double model = 0.5 * trial.dot(p_.S * trial) - cy.dot(trial) + model_value(trial);
      const double predicted = fc - model;
      const double ft = f1(trial, &quad) - y.dot(trial);
      const double rt = residual(trial, y);
      add_cuts(trial, y);
      if (p_.groups.empty())
        compress(env);
      else
        compress_groups();
      for (const auto& ci : cuts_) largest_bundle = std::max(largest_bundle, ci.size());
      for (const auto& ci : plane_cuts_) largest_bundle = std::max(largest_bundle, ci.size());
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
      if (!p_.groups.empty() && rc > inner_tol && run_.budget_left(2)) polish(center, fc, rc, y);
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
    if (p_.groups.empty()) {
      for (Eigen::Index i = 0; i < n_; ++i) s += p_.w(i) * p_.law_of(i).value(LawPart::j1, a(i));
      return s;
    }
    for (Eigen::Index i = 0; i < n_; ++i)
      if (group_of_(i) < 0) s += p_.w(i) * p_.law_of(i).value(LawPart::j1, a(i));
    for (const CoordinateGroup& g : p_.groups) s += p_.w(g.first) * p_.law_of(g.first).value(LawPart::j1, group_norm(a, g));
    return s;
  }

  // With groups, a cutting-plane model of a pair resolves the direction of a slipping group only
  // to about the square root of the rounding (the linearisation error is quadratic in the angle
  // it misses): Newton steps on f_k itself, on the face of the center (a group at the origin, a
  // coordinate at a kink of j1 or at a bound stays there; elsewhere j1 is smooth), replace the
  // center when they lower f_k (up to rounding) and its residual.
  void polish(Eigen::VectorXd& center, double& fc, double& rc, const Eigen::VectorXd& y) {
    for (int step = 0; step < 4 && run_.budget_left(2); ++step) {
      Eigen::MatrixXd K = p_.S;
      Eigen::VectorXd grad = p_.S * center - p_.c - y;
      std::vector<char> fixed(U(n_), 0);
      for (Eigen::Index i = 0; i < n_; ++i) {
        if (group_of_(i) >= 0) continue;
        const ContactLaw& law = p_.law_of(i);
        const double x = center(i), dl = law.derivative(LawPart::j1, x, -1), dr = law.derivative(LawPart::j1, x, +1);
        if (dl != dr || x == p_.lower(i) || x == p_.upper(i)) {
          fixed[U(i)] = 1;
          continue;
        }
        grad(i) += p_.w(i) * dr;
        K(i, i) += p_.w(i) * law.second_derivative(LawPart::j1, x, +1);
      }
      for (const CoordinateGroup& g : p_.groups) {
        const Eigen::Vector2d v(center(g.first), center(g.second));
        const double r = v.norm(), w = p_.w(g.first);
        const ContactLaw& law = p_.law_of(g.first);
        const double dl = law.derivative(LawPart::j1, r, -1), dr = law.derivative(LawPart::j1, r, +1);
        if (r == 0.0 || dl != dr) {
          fixed[U(g.first)] = fixed[U(g.second)] = 1;
          continue;
        }
        const Eigen::Vector2d e = v / r;
        const Eigen::Matrix2d P = e * e.transpose();
        const Eigen::Matrix2d Hg = w * law.second_derivative(LawPart::j1, r, +1) * P + (w * dr / r) * (Eigen::Matrix2d::Identity() - P);
        grad(g.first) += w * dr * e(0);
        grad(g.second) += w * dr * e(1);
        K(g.first, g.first) += Hg(0, 0);
        K(g.first, g.second) += Hg(0, 1);
        K(g.second, g.first) += Hg(1, 0);
        K(g.second, g.second) += Hg(1, 1);
      }
      std::vector<Eigen::Index> free;
      for (Eigen::Index i = 0; i < n_; ++i)
        if (!fixed[U(i)]) free.push_back(i);
      if (free.empty()) return;
      const Eigen::Index nf = static_cast<Eigen::Index>(free.size());
      Eigen::MatrixXd Kff(nf, nf);
      Eigen::VectorXd gf(nf);
      for (Eigen::Index a = 0; a < nf; ++a) {
        gf(a) = grad(free[U(a)]);
        for (Eigen::Index b = 0; b < nf; ++b) Kff(a, b) = K(free[U(a)], free[U(b)]);
      }
      const Eigen::LLT<Eigen::MatrixXd> llt(Kff);
      if (llt.info() != Eigen::Success) return;
      const Eigen::VectorXd d = llt.solve(-gf);
      if (!d.allFinite()) return;
      Eigen::VectorXd x = center;
      for (Eigen::Index a = 0; a < nf; ++a) x(free[U(a)]) += d(a);
      x = p_.project(x);
      const double fx = f1(x) - y.dot(x);
      run_.count_subgradients();
      const double rx = residual(x, y);
      const double noise = 1e-13 * (std::abs(fc) + 1e-300);
      if (!(fx <= fc + noise && rx < rc)) return;
      center = x;
      fc = fx;
      rc = rx;
    }
  }

  // The value of the cutting-plane model of the nonsmooth part of F1 at a.
  double model_value(const Eigen::VectorXd& a) const {
    if (p_.groups.empty()) return hemivem::model_value(cuts_, a);
    double m = 0.0;
    for (Eigen::Index i = 0; i < n_; ++i)
      if (group_of_(i) < 0) m += line_model(cuts_[U(i)], a(i));
    for (std::size_t k = 0; k < p_.groups.size(); ++k)
      m += plane_model(plane_cuts_[k], Eigen::Vector2d(a(p_.groups[k].first), a(p_.groups[k].second)));
    return m;
  }

  // The cuts of phi_G(v) = w j1(|v|) at a's pairs: at r = |v| > 0 the linearisations with the
  // one-sided derivatives of j1 along v / r; at the origin, and wherever the residual
  // rho = (c + y - S a)_G of the subproblem lies in the disc of radius w j1'(0+) (the group
  // looks stuck), the cut of slope rho projected onto the disc and, when the disc is not a
  // point, the two of slope on its circle at +-120 degrees from it: their maximum has a vertex
  // at the origin whose subdifferential contains that slope.
  void add_plane_cuts(const Eigen::VectorXd& a, const Eigen::VectorXd& y) {
    const Eigen::VectorXd rho = p_.c + y - p_.S * a;
    for (std::size_t k = 0; k < p_.groups.size(); ++k) {
      const CoordinateGroup& g = p_.groups[k];
      const ContactLaw& law = p_.law_of(g.first);
      const double w = p_.w(g.first);
      const Eigen::Vector2d v(a(g.first), a(g.second)), res(rho(g.first), rho(g.second));
      const double r = v.norm(), radius = w * law.derivative(LawPart::j1, 0.0, +1);
      auto& ck = plane_cuts_[k];
      const std::size_t before = ck.size();
      if (r > 0.0) {
        const double value = w * law.value(LawPart::j1, r);
        const double sr = w * law.derivative(LawPart::j1, r, +1);
        ck.push_back({value - sr * r, sr * (v / r)});
        if (o_.two_sided_cuts) {
          const double sl = w * law.derivative(LawPart::j1, r, -1);
          if (sl != sr) ck.push_back({value - sl * r, sl * (v / r)});
        }
      }
      const double m = res.norm();
      if (r == 0.0 || m <= radius) {
        const double base = w * law.value(LawPart::j1, 0.0);
        const Eigen::Vector2d s = m <= radius ? res : Eigen::Vector2d(res * (radius / m));
        ck.push_back({base, s});
        if (radius > 0.0) {
          const Eigen::Vector2d e = m > 0.0 ? Eigen::Vector2d(res / m) : Eigen::Vector2d(1.0, 0.0);
          const double c = -0.5, sn = 0.5 * std::sqrt(3.0);
          ck.push_back({base, radius * Eigen::Vector2d(c * e(0) - sn * e(1), sn * e(0) + c * e(1))});
          ck.push_back({base, radius * Eigen::Vector2d(c * e(0) + sn * e(1), -sn * e(0) + c * e(1))});
        }
      }
      plane_added_[k] = static_cast<int>(ck.size() - before);
    }
  }

  // The dual residual of the DC subproblem min_C F1 - y^T a (the certificate's rule with j1
  // for j and c + y for c, at the point as it is).
  double residual(const Eigen::VectorXd& a, const Eigen::VectorXd& y) const {
    const Eigen::VectorXd Sa = p_.S * a;
    double worst = 0.0, scale = std::max((p_.c + y).cwiseAbs().maxCoeff(), Sa.cwiseAbs().maxCoeff());
    for (const CoordinateGroup& g : p_.groups) {
      // the certificate's rule for a pair, with j1: the law force on the ray of v at a length in
      // w [j1'(r-), j1'(r+)], or in the disc of radius w j1'(0+) at the origin
      const Eigen::Vector2d res(Sa(g.first) - p_.c(g.first) - y(g.first), Sa(g.second) - p_.c(g.second) - y(g.second));
      const Eigen::Vector2d v(a(g.first), a(g.second));
      const double r = v.norm(), w = p_.w(g.first);
      const ContactLaw& law = p_.law_of(g.first);
      Eigen::Vector2d zeta;
      if (r > 0.0) {
        const Eigen::Vector2d e = v / r;
        double dl = law.derivative(LawPart::j1, r, -1), dr = law.derivative(LawPart::j1, r, +1);
        if (dl > dr) std::swap(dl, dr);
        zeta = Interval{w * dl, w * dr}.nearest(-res.dot(e)) * e;
      } else {
        const double radius = w * law.derivative(LawPart::j1, 0.0, +1), m = res.norm();
        zeta = m <= radius ? Eigen::Vector2d(-res) : Eigen::Vector2d(-res * (radius / m));
      }
      worst = std::max(worst, (res + zeta).norm());
      scale = std::max(scale, zeta.cwiseAbs().maxCoeff());
    }
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (group_of_(i) >= 0) continue;
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

  // compress() for a problem with groups: per coordinate on its own and per group, the cuts
  // active at the subproblem solution, the newest, then the most recent others.
  void compress_groups() {
    auto keep_some = [&](auto& list, const std::vector<int>& active, int newest) {
      if (static_cast<int>(list.size()) <= o_.bundle_size) return;
      std::vector<char> keep(list.size(), 0);
      for (int k : active)
        if (k >= 0 && U(k) < list.size()) keep[U(k)] = 1;
      for (int j = 0; j < newest; ++j) keep[list.size() - 1 - U(j)] = 1;
      int count = static_cast<int>(std::count(keep.begin(), keep.end(), 1));
      for (std::size_t j = list.size(); j-- > 0 && count < o_.bundle_size;)
        if (!keep[j]) keep[j] = 1, ++count;
      std::remove_reference_t<decltype(list)> kept;
      for (std::size_t j = 0; j < list.size(); ++j)
        if (keep[j]) kept.push_back(list[j]);
      list.swap(kept);
    };
    for (Eigen::Index i = 0; i < n_; ++i)
      if (group_of_(i) < 0) keep_some(cuts_[U(i)], faces_[U(i)].active, added_[U(i)]);
    for (std::size_t k = 0; k < p_.groups.size(); ++k)
      keep_some(plane_cuts_[k], faces_[U(p_.groups[k].first)].active, plane_added_[k]);
  }

  MinimizerRun& run_;
  const ReducedProblem& p_;
  const BundleDcaOptions& o_;
  const Eigen::Index n_;
  double mu_ = 0.0;
  Eigen::MatrixXd H_;                   // S + mu I
  std::vector<std::vector<Cut>> cuts_;  // per coordinate (on its own)
  std::vector<int> added_;              // cuts added last per coordinate (at the tail)
  QpState state_;
  const Eigen::VectorXi group_of_;                 // per coordinate its group or -1
  std::vector<std::vector<PlaneCut>> plane_cuts_;  // per group
  std::vector<int> plane_added_;                   // cuts added last per group (at the tail)
  std::vector<BlockFace> faces_;                   // the faces of the last subproblem solution
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
    // DC step: linearise F2 at a, solve min_C F1 - y^T a. With j convex (j2 = 0 for the shipped
    // convex laws) the subproblem is F itself, solved to the final accuracy at once.
    const Eigen::VectorXd y = p.subgradient_convex2(a);
    if (k == 1) bundle.add_cuts(a, y);
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
