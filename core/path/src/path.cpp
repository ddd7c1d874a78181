#include <hemivem/path/path.hpp>

#include "anderson.hpp"
#include "solved_loads.hpp"

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/supports.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/error.hpp>
#include <hemivem/process_group.hpp>
#include <hemivem/support/blas_threads.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace hemivem {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

template <int dim>
void check_loading(const BasicPathLoading<dim>& loading) {
  if (loading.t.empty()) throw InputError("a loading path needs at least one load factor t");
  for (std::size_t k = 0; k < loading.t.size(); ++k) {
    const double t = loading.t[k];
    if (!(std::isfinite(t) && t > 0.0))
      throw InputError("load factor " + std::to_string(k + 1) + " of the path must be finite and > 0, got " +
                       std::to_string(t));
    if (k > 0 && !(t > loading.t[k - 1]))
      throw InputError("the load factors of a path must increase: t_" + std::to_string(k + 1) + " = " +
                       std::to_string(t) + " after t_" + std::to_string(k) + " = " + std::to_string(loading.t[k - 1]));
  }
}

// A field (of points to numbers or to vectors) multiplied by s; empty stays empty.
template <class Field>
Field times(const Field& f, double s) {
  if (!f) return f;
  return [f, s](const auto& x) {
    auto v = f(x);
    v *= s;
    return v;
  };
}

// The problem's loads and prescribed displacements multiplied by s (the proportional path's
// data at t = s), for the balance of forces of a frame.
template <class Elasticity>
Elasticity scaled(const Elasticity& p, double s) {
  Elasticity q = p;
  q.body_force = times(p.body_force, s);
  for (auto& load : q.tractions) {
    load.traction = times(load.traction, s);
    load.pressure = times(load.pressure, s);
  }
  for (auto& d : q.dirichlet) d.value = times(d.value, s);
  return q;
}

// The path's verdict is its first failure: when a step did not converge, the last solution
// (what a run reports, its status and exit code) carries that step's status and says which step
// it was and that the steps after it started from its uncertified state.
template <int dim>
void carry_first_failure(BasicPathSolution<dim>& out, const std::optional<BasicPathStep<dim>>& failed) {
  if (!failed) return;
  std::ostringstream why;
  why << "step " << failed->index << " (t = " << failed->t << ") did not converge: " << to_string(failed->status);
  if (!failed->message.empty()) why << " (" << failed->message << ")";
  if (const int later = out.solved_steps - failed->index; later > 0)
    why << "; the " << later << (later == 1 ? " step" : " steps") << " after it started from its uncertified state";
  if (out.last.converged()) out.last.status = failed->status;
  out.last.message = why.str();
}

// The resultant of a vector of dim components per vertex.
template <int dim>
Eigen::Matrix<double, dim, 1> resultant(const Eigen::VectorXd& f) {
  Eigen::Matrix<double, dim, 1> r = Eigen::Matrix<double, dim, 1>::Zero();
  for (Eigen::Index d = 0; d + dim - 1 < f.size(); d += dim) r += f.segment<dim>(d);
  return r;
}

// The prescribed dofs, in order.
std::vector<int> held_dofs(const DofMap& dofs) { return dofs.prescribed_dofs(); }

// One vector of a step's load for SolvedLoads, into v: the free dofs' right-hand side b, then
// the values of the prescribed dofs (DofMap::prescribed_values); and back, with the prescribed
// dofs `held`.
void stack(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed_values, Eigen::VectorXd* v) {
  v->resize(b.size() + prescribed_values.size());
  v->head(b.size()) = b;
  v->tail(prescribed_values.size()) = prescribed_values;
}

void unstack(const std::vector<int>& held, const Eigen::VectorXd& v, Eigen::VectorXd* b, Eigen::VectorXd* prescribed) {
  const Eigen::Index free = v.size() - static_cast<Eigen::Index>(held.size());
  *b = v.head(free);
  *prescribed = Eigen::VectorXd::Zero(v.size());
  for (std::size_t j = 0; j < held.size(); ++j) (*prescribed)(held[j]) = v(free + static_cast<Eigen::Index>(j));
}

// Contact node i's outward normal.
template <int dim>
Eigen::Matrix<double, dim, 1> normal_of(const ContactBoundary& boundary, int i) {
  if constexpr (dim == 2)
    return boundary.normals[static_cast<std::size_t>(i)];
  else
    return boundary.normals3d[static_cast<std::size_t>(i)];
}

std::string shortest(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

}  // namespace

Certificate friction_bound_certificate(const Certificate& tresca, const Eigen::VectorXd& weights,
                                       const Eigen::VectorXd& used, const Eigen::VectorXd& implied) {
  Certificate c = tresca;
  double mismatch = 0.0;
  for (Eigen::Index i = 0; i < used.size(); ++i) {
    const double d = weights(i) * std::abs(used(i) - implied(i));
    mismatch = std::isnan(d) ? std::numeric_limits<double>::infinity() : std::max(mismatch, d);
  }
  if (mismatch > 0.0) {
    const double relative = std::isfinite(mismatch) && c.force_scale > 0.0 ? mismatch / c.force_scale
                                                                             : std::numeric_limits<double>::infinity();
    c.dual = std::max(c.dual, relative);
  }
  return c;
}

template <int dim>
struct BasicPathSolver<dim>::Impl {
  using Problem = BasicContactProblem<dim>;
  using Point = Eigen::Matrix<double, dim, 1>;
  using Step = BasicPathStep<dim>;
  Problem& problem;
  std::unique_ptr<SparseFactorization> factorization;
  std::unique_ptr<KrylovSolver> krylov;  // the full-space route's engine (null: the condensed route)
  const NonsmoothMinimizer& minimizer;
  BasicPathLoading<dim> loading;
  BasicPathOptions<dim> options;

  // the stages of the static solve that set the path up: assembly, boundary, supports, condensation
  std::unique_ptr<BasicContactSolver<dim>> pipeline;
  const LinearSystem* system = nullptr;
  // The free dofs' numbering, the system's (across processes the posed share's), with the
  // prescribed values of the step: the path's own copy (step_dofs) where they change along it.
  const DofMap* dofs = nullptr;
  std::optional<DofMap> step_dofs;
  ContactBoundary boundary;      // the pipeline's, with the gaps of the step
  Condensation* cond = nullptr;
  std::vector<std::string> held_by_contact;
  ReducedProblem step;           // the step's problem: the condensation's, with c, bounds and weights of the step
  int n1 = 0;                    // contact nodes
  std::vector<BasicContactPart<dim>> parts;
  bool any_bilateral = false;    // a node without a normal unknown (its normal force needs the displacement)
  bool has_tangential = false;   // a node with a tangential unknown
  /// Per contact node, the friction bound of its part that depends on the normal contact (null: none).
  std::vector<const FrictionBound*> bound_law;
  bool bounded = false;          // some node has one
  // The loads condensed so far (a proportional path: the one at t = 1; a path whose load is a
  // combination of fields with coefficients in t: one per field) and what each gives: its
  // condensed load (column j of load_c), its applied resultant, and load_kappa, with
  // kappa(V alpha) = alpha^T K alpha = Phi(u) - [1/2 x^T S x - c^T x] for the load V alpha.
  detail::SolvedLoads loads;
  std::vector<int> held;         // the prescribed dofs
  Eigen::VectorXd v;             // the step's load, stacked (data_at: a path with an update)
  Eigen::MatrixXd load_c;
  Eigen::Matrix<double, dim, Eigen::Dynamic> load_applied;
  Eigen::MatrixXd load_kappa;
  Eigen::VectorXd alpha;         // the step's load is V alpha (empty: a load outside the span)
  bool load_current = true;      // the condensation holds the step's load (set_load)
  std::string through;           // the step's obstacle has moved through the body (passed_through)
  int condensed_loads = 1;       // the condensation's own, then one per interior solve of a step's load
  // along the path
  Eigen::VectorXd x_prev;        // the previous step's contact unknowns (u_nu, u_tau)
  Eigen::VectorXd tau_prev;      // the previous step's tangential displacements, per reduced coordinate (0 on the normals)
  Eigen::VectorXd g;             // the friction bound per node (FrictionBound)
  Eigen::VectorXd g_before;      // the bound the step before the last ended with (empty before it)
  double change_prev = 0.0, t_prev = 0.0, t_before = 0.0;
  std::map<std::string, double> timings;
  FullSpaceStatistics full_space_counts;  // the full-space route's, summed over the path's minimizations
  bool check_existence_each_step = true;
  // the full-space route: the rotated free unknowns of the last minimization (each step starts
  // from the one before), and a proportional path's load and prescribed values at t = 1 (in one
  // process; across processes each scales its own rows) and resultant
  bool full = false;
  // across processes (options.distribute): each process's share, and the residual (rotated, of
  // the process's own rows) and quadratic energy of the last point found
  std::unique_ptr<FullSpaceShares<dim>> shares;
  Eigen::VectorXd shares_residual;
  double shares_quadratic = 0.0;
  // the rotated free unknowns of the last point found: every one in one process, the process's
  // own rows across processes (gathered only where a step's displacement is made)
  Eigen::VectorXd xt;
  Eigen::VectorXd full_b, full_prescribed;
  Point full_applied = Point::Zero();

  Impl(Problem& p, std::unique_ptr<SparseFactorization> f, std::unique_ptr<KrylovSolver> k, const NonsmoothMinimizer& m,
       BasicPathLoading<dim> l, BasicPathOptions<dim> o)
      : problem(p),
        factorization(std::move(f)),
        krylov(std::move(k)),
        minimizer(m),
        loading(std::move(l)),
        options(std::move(o)),
        full(krylov != nullptr) {}

  void set_up();
  void condense();
  void remember_load(const Eigen::VectorXd& b);
  Eigen::VectorXd step_load(Step& s, Eigen::VectorXd* b, double* kappa);
  void data_at(const Step& s);
  void posed_load(Step& s, Eigen::VectorXd* b);
  /// The resultant of the applied load of `e` (the problem at the moment): across processes each
  /// sums its own vertices (FullSpaceShares::applied), exact on its piece of the mesh.
  Point applied_of(const BasicElasticityProblem<dim>& e) const {
    return shares ? shares->applied(e) : resultant<dim>(assemble_load(*e.mesh, e.body_force, e.tractions));
  }
  /// The full-space route's load of the step on the posed system (and the share's rows).
  void set_posed_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed) {
    if (shares)
      shares->set_load(b, prescribed);
    else
      cond->set_load(b, prescribed);
  }
  MinimizerResult minimize_once(const Eigen::VectorXd& from, const Eigen::VectorXd& origin);
  void minimize_alone(Step& s, const Eigen::VectorXd& from, const Eigen::VectorXd& origin);
  void make_load_current(Eigen::VectorXd* b);
  void find_friction_bounds();
  /// The tangential weights w_i g_i of `nodes` (those whose bound depends on the normal
  /// contact) on each of their tangential coordinates: the step's Tresca problem for the bound g.
  void set_bound_weights(const std::vector<int>& nodes) {
    for (int i : nodes)
      for (const int kt : tangential_coordinates(i))
        if (kt >= 0) step.w(kt) = boundary.weights(i) * g(i);
  }
  /// Contact node i's tangential coordinates (-1: none): one in the plane, two (a group) on a
  /// solid's surface with both tangentials free.
  std::array<int, 2> tangential_coordinates(int i) const {
    return {cond->tangential_coordinate(i), cond->second_tangential_coordinate(i)};
  }
  Step solve_step(int k);
  void extrapolate_bound(double t);
  // The full nodal displacement of the last point found on the full-space route (across
  // processes gathered from every process's rows: collective).
  Eigen::VectorXd displacement() const {
    return cond->displacement_of(shares ? shares->distribution().all_gather(xt) : xt);
  }
  std::string passed_through(const Eigen::VectorXd& before) const;
  void minimize_step(Step& s, const Eigen::VectorXd& shift, const Eigen::VectorXd& origin, bool unloaded);
  void describe_step(Step& s, const MinimizerResult& m, const Eigen::VectorXd& shift,
                     const Eigen::VectorXd& c_raw, double kappa, const Eigen::VectorXd* u,
                     const Eigen::VectorXd* b);
  BasicContactSolution<dim> last_solution(const Step& s, const MinimizerResult& m, const Eigen::VectorXd& shift);
  MinimizerResult last_result;
  Eigen::VectorXd last_shift;
};

template <int dim>
void BasicPathSolver<dim>::Impl::set_up() {
  check_loading(loading);
  if (!factorization && !krylov) throw InputError("a path needs a linear engine");
  if (krylov && minimizer.name() != "ssn")
    throw InputError("the full-space route (linear engine " + krylov->name() +
                     ") runs its own semismooth Newton iteration, the minimizer ssn: minimizer " + minimizer.name() +
                     " needs a linear engine that factorizes");
  if (options.distribute && !krylov)
    throw InputError("a loading path across processes runs on the full-space route: it needs a Krylov engine");
  if (factorization && processes_of(*factorization).num_processes() != 1)
    throw InputError("a loading path runs in one process; the linear engine " + factorization->name() +
                     " runs across processes: choose another");
  if (std::string why; !options.minimizer.is_valid(&why)) throw InputError(why, "MinimizerOptions");
  if (!(options.jump_factor > 1.0)) throw InputError("the jump factor of a path must be > 1");
  if (options.solved_loads < 0) throw InputError("the number of loads a path keeps condensed must be >= 0");
  if (options.fixed_point.max_iterations < 1 || !(options.fixed_point.relaxation > 0.0 && options.fixed_point.relaxation <= 1.0))
    throw InputError("the fixed point of a path needs max_iterations >= 1 and a relaxation in (0, 1]");
  if (problem.parts.empty())
    throw InputError("a loading path needs a contact boundary (without one the displacement at t is t times the one at t = 1)");
  parts = contact_parts(problem);
  for (const auto& part : parts) {
    const std::string which = parts.size() == 1 ? std::string() : " of contact part '" + part.name + "'";
    if (!part.law)
      throw InputError(parts.size() == 1 ? std::string("the contact boundary has no contact law")
                                         : "contact part '" + part.name + "' has no contact law");
    if (!part.friction_bound) continue;
    check_friction_bound(*part.friction_bound, parts.size() == 1 ? std::string("contact.friction") : "contact part '" + part.name + "'");
    if (!part.friction)
      throw InputError("a friction bound that depends on the normal contact needs the friction law tresca_law(1)" + which);
    if (constraint_in_effect(part) == ConstraintKind::bilateral)
      throw InputError("a friction bound that depends on the normal contact needs the normal displacements as unknowns, "
                       "which a bilateral constraint (u_nu = 0) removes" + which);
  }
  if (!loading.proportional()) loading.update(loading.t.front(), problem);
  condense();
  find_friction_bounds();
  x_prev = Eigen::VectorXd::Zero(step.size());
  tau_prev = Eigen::VectorXd::Zero(step.size());
  g = Eigen::VectorXd::Zero(n1);
  if (full) {  // nothing condensed: a step's load is set on the posed system
    condensed_loads = 0;
    if (!shares) {  // across processes the shares scale their own rows (FullSpaceShares::scale_load)
      full_b = system->b;
      full_prescribed = dofs->prescribed();
    }
    full_applied = applied_of(problem.elasticity);
    return;
  }
  // a proportional path keeps its load at t = 1 whatever the capacity
  const int capacity = loading.proportional() ? std::max(1, options.solved_loads) : options.solved_loads;
  loads = detail::SolvedLoads(dofs->num_dofs(), capacity, 1e-12);
  load_c.resize(step.size(), 0);
  load_applied.resize(dim, 0);
  held = held_dofs(*dofs);
  stack(system->b, dofs->prescribed_values(), &v);
  if (!loads.full() && !v.isZero(0.0)) remember_load(system->b);
}

// Keeps the load the condensation holds (the first step's; a proportional path's at t = 1)
// with its condensed load, resultant and kappa: Phi at the displacement u0 whose contact
// unknowns are 0 (1/2 x^T S x - c^T x = 0 there), K_jj = 1/2 u0.A u0 - u0.b_j and, as A u0 = b
// away from the contact unknowns, K_ij = -1/2 u0_j . b_i.
template <int dim>
void BasicPathSolver<dim>::Impl::remember_load(const Eigen::VectorXd& b) {
  stack(b, dofs->prescribed_values(), &v);
  const auto j = static_cast<Eigen::Index>(loads.add(v));
  load_c.conservativeResize(Eigen::NoChange, j + 1);
  load_c.col(j) = cond->condensed_load();
  load_applied.conservativeResize(Eigen::NoChange, j + 1);
  load_applied.col(j) = applied_of(problem.elasticity);
  const Eigen::VectorXd u0 = cond->back_substitute(-cond->origin());
  const Eigen::VectorXd uf = dofs->free_part(u0);
  load_kappa.conservativeResize(j + 1, j + 1);
  load_kappa(j, j) = 0.5 * uf.dot(system->A * uf) - uf.dot(b);
  for (Eigen::Index i = 0; i < j; ++i)
    load_kappa(i, j) = load_kappa(j, i) = -0.5 * uf.dot(loads.loads().col(i).head(dofs->num_free()));
}

// The step's condensed load c_raw, its resultant (s.applied) and, when the load is in the span of
// those kept, kappa (else NaN) and alpha: a proportional path's is t times the load at t = 1;
// otherwise the scene's data at t are assembled (b) and written as a combination of the loads
// kept, or condensed anew (one interior solve) and kept while there is room.
template <int dim>
Eigen::VectorXd BasicPathSolver<dim>::Impl::step_load(Step& s, Eigen::VectorXd* b, double* kappa) {
  load_current = false;
  through.clear();
  if (loading.proportional()) {
    alpha = Eigen::VectorXd::Constant(loads.size(), s.t);
  } else {
    data_at(s);
    if (auto found = loads.coefficients(v)) {
      alpha = std::move(*found);
    } else {
      *b = v.head(dofs->num_free());
      if (s.index > 1) {  // the first step's load is the condensation's own
        cond->set_load(*b, dofs->prescribed());
        ++condensed_loads;
      }
      load_current = true;
      if (loads.full()) {
        alpha.resize(0);
        *kappa = std::numeric_limits<double>::quiet_NaN();
        s.applied = applied_of(problem.elasticity);
        return cond->condensed_load();
      }
      remember_load(*b);
      alpha = Eigen::VectorXd::Unit(loads.size(), loads.size() - 1);
    }
  }
  // kappa as the proportional path always formed it, (t t) K_11
  *kappa = 0.0;
  for (Eigen::Index i = 0; i < alpha.size(); ++i)
    for (Eigen::Index j = 0; j < alpha.size(); ++j) *kappa += alpha(i) * alpha(j) * load_kappa(i, j);
  s.applied = alpha.size() == 1 ? Point(alpha(0) * load_applied.col(0)) : Point(load_applied * alpha);
  return alpha.size() == 1 ? Eigen::VectorXd(alpha(0) * load_c.col(0)) : Eigen::VectorXd(load_c * alpha);
}

// The scene's data at the step's t (a path with an update): its prescribed values (dofs), its
// load stacked in v (the free dofs' right-hand side, assembled in place, then the values of the
// prescribed dofs `held`), and its gaps, bounds and laws (boundary, the condensation, step).
template <int dim>
void BasicPathSolver<dim>::Impl::data_at(const Step& s) {
  if (s.index > 1) loading.update(s.t, problem);
  if (loading.updates_prescribed) {
    const DofMap at_t = make_dof_map(*problem.elasticity.mesh, problem.elasticity.dirichlet);
    if (held_dofs(at_t) != held_dofs(*dofs))
      throw InputError("the prescribed degrees of freedom change along the path at t = " + shortest(s.t) +
                       ": a path may change prescribed values, not which displacements are prescribed");
    if (!step_dofs) {
      step_dofs = *dofs;
      dofs = &*step_dofs;
    }
    step_dofs->set_prescribed_values(at_t.prescribed_values());
  }
  const Eigen::Index free = dofs->num_free();
  v.resize(free + static_cast<Eigen::Index>(held.size()));
  assemble_rhs(problem.elasticity, *dofs, v.head(free));
  v.tail(static_cast<Eigen::Index>(held.size())) = dofs->prescribed_values();
  if (loading.updates_gaps) {
    const Eigen::VectorXd before = boundary.gaps;
    boundary.gaps = contact_boundary(problem, *dofs).gaps;  // the contact nodes report the step's gaps
    through = passed_through(before);
    cond->set_gaps(boundary.gaps);
    step.lo = cond->reduced().lo;
    step.hi = cond->reduced().hi;
    if (step.laws.size() != cond->reduced().laws.size()) step.laws = cond->reduced().laws;
    step.law_index = cond->reduced().law_index;
  }
}

// The full-space route's load of the step, set on the posed system (no solve): a proportional
// path's is t times the one at t = 1, otherwise the scene's data at t.
template <int dim>
void BasicPathSolver<dim>::Impl::posed_load(Step& s, Eigen::VectorXd* b) {
  through.clear();
  if (loading.proportional()) {
    if (shares) {
      shares->scale_load(s.t);
    } else {
      *b = s.t * full_b;
      cond->set_load(*b, s.t * full_prescribed);
    }
    s.applied = s.t * full_applied;
    return;
  }
  data_at(s);
  *b = v.head(dofs->num_free());
  set_posed_load(*b, dofs->prescribed());
  s.applied = applied_of(problem.elasticity);
  if (shares) {  // the shares hold their rows of it: nothing of the whole load is kept through the solve
    *b = Eigen::VectorXd();
    v = Eigen::VectorXd();
  }
}

// One minimization of the step's problem from `from` (its coordinates; on the full-space route
// the rotated unknowns xt, which it leaves at the point found) with the coordinates' origin.
template <int dim>
MinimizerResult BasicPathSolver<dim>::Impl::minimize_once(const Eigen::VectorXd& from, const Eigen::VectorXd& origin) {
  if (!full) return minimizer.minimize(step, from, options.minimizer);
  FullSpaceStatistics statistics;
  MinimizerResult m;
  if (shares) {
    auto point = shares->minimize(step, origin, options.minimizer, xt, &statistics);
    m = std::move(point.result);
    xt = std::move(point.x);
    shares_residual = std::move(point.residual);
    shares_quadratic = point.quadratic;
  } else {
    m = pipeline->minimize_posed(step, origin, &xt, &statistics);
  }
  timings["preconditioner"] += statistics.preconditioner_seconds;
  timings["krylov"] += statistics.krylov_seconds;
  full_space_counts += statistics;
  return m;
}

// A contact node whose gap was finite and is infinite now, with its part's obstacle behind it
// (the ray into the body meets it): the obstacle has moved through the body's surface there, and
// the contact (a rigid obstacle outside the body) no longer describes it. Empty when there is none,
// else what happened, naming the first such node.
template <int dim>
std::string BasicPathSolver<dim>::Impl::passed_through(const Eigen::VectorXd& before) const {
  for (int i = 0; i < n1; ++i) {
    if (!std::isfinite(before(i)) || std::isfinite(boundary.gaps(i))) continue;
    const auto& part = problem.parts[static_cast<std::size_t>(boundary.part_of(i))];
    if (!part.obstacle) continue;
    const int v = boundary.nodes[static_cast<std::size_t>(i)];
    const auto x = problem.elasticity.mesh->vertex(v);
    const auto nu = normal_of<dim>(boundary, i);
    if (!std::isfinite(part.obstacle->gap(x, -nu))) continue;
    std::ostringstream out;
    out << "the obstacle of contact part '" << part.name << "' has moved through the body's surface at vertex " << v
        << " (";
    for (int d = 0; d < dim; ++d) out << (d ? ", " : "") << shortest(x(d));
    out << "): its gap went from " << shortest(before(i))
        << " to infinite, with the obstacle behind the node; the contact holds for an obstacle outside the body";
    return out.str();
  }
  return {};
}

// Sets the condensation's load to the step's, for its displacement: b as assembled, or (empty)
// the combination of the loads kept, which it is then set to.
template <int dim>
void BasicPathSolver<dim>::Impl::make_load_current(Eigen::VectorXd* b) {
  if (load_current) return;
  // a path with an update assembled the step's own load into v (data_at)
  if (b->size() != dofs->num_free() && !loading.proportional()) *b = v.head(dofs->num_free());
  if (b->size() == dofs->num_free()) {
    cond->set_load(*b, dofs->prescribed());
  } else {
    Eigen::VectorXd prescribed;
    unstack(held, loads.combination(alpha), b, &prescribed);
    cond->set_load(*b, prescribed);
  }
  load_current = true;
}

// The stages of the static solve up to the condensation (BasicContactSolver::prepare).
template <int dim>
void BasicPathSolver<dim>::Impl::condense() {
  if (full && options.distribute) {  // across processes: this process's share, the whole surface
    shares = std::make_unique<FullSpaceShares<dim>>(problem, *krylov, options.world, options.distribute,
                                                    options.vertex_order);
    dofs = &shares->dofs();
    parts = shares->contact().parts;
    boundary = shares->contact().boundary;
    held_by_contact = shares->contact().held_by_contact;
    // as in one process, where the contact's set-up is not one of the path's stages
    timings["assembly"] = shares->timings().at("assembly");
    timings["posing"] = shares->timings().at("setup") + shares->timings().at("posing");
    cond = &shares->posed();
  } else {
    pipeline = full ? std::make_unique<BasicContactSolver<dim>>(problem, std::move(krylov), options.minimizer)
                    : std::make_unique<BasicContactSolver<dim>>(problem, std::move(factorization), options.minimizer);
    pipeline->prepare();
    system = &pipeline->system();
    dofs = &system->dofs;
    parts = pipeline->parts();
    boundary = pipeline->boundary();
    held_by_contact = pipeline->prepared().held_by_contact;
    for (const char* stage : {"assembly", "condensation", "posing"})
      if (const auto it = pipeline->prepared().timings.find(stage); it != pipeline->prepared().timings.end())
        timings[stage] = it->second;
    cond = pipeline->condensation();
  }
  if (boundary.size() == 0) throw InputError("the contact boundary of the path has no free node");
  step = cond->reduced();
  n1 = boundary.size();
  // S does not change along the path: whether F is bounded below is decided once, at the first
  // step (every step when a rigid motion is held by the contact only, where it depends on c)
  check_existence_each_step = !held_by_contact.empty();
}

// Per node, the friction bound that depends on the normal contact (FrictionBound), if any.
template <int dim>
void BasicPathSolver<dim>::Impl::find_friction_bounds() {
  bound_law.assign(static_cast<std::size_t>(n1), nullptr);
  for (int i = 0; i < n1; ++i) {
    any_bilateral = any_bilateral || cond->normal_coordinate(i) < 0;
    has_tangential = has_tangential || cond->tangential_coordinate(i) >= 0;
    const auto& part = parts[static_cast<std::size_t>(boundary.part_of(i))];
    // a node whose tangential displacement a support prescribes has no friction coordinate
    if (!part.friction_bound || cond->tangential_coordinate(i) < 0) continue;
    bound_law[static_cast<std::size_t>(i)] = &*part.friction_bound;
    bounded = true;
    // the tangential coordinate's law is g |r| with g = 1: the node's bound is its weight
    const int k = cond->tangential_coordinate(i);
    if (step.law_of(k).name() != "tresca" || std::abs(step.law_of(k).derivative(LawPart::j, 1.0, +1) - 1.0) > 0.0)
      throw InputError("a friction bound that depends on the normal contact needs the friction law tresca_law(1)");
  }
}

// The step's problem is F in the variable a' = x - origin - shift (x the contact unknowns, origin
// the gaps of law_from_surface, shift the previous u_tau on the tangential coordinates): its c
// is c_raw - S (origin + shift), its bounds the condensation's.
template <int dim>
auto BasicPathSolver<dim>::Impl::solve_step(int k) -> Step {
  const auto t_start = Clock::now();
  Step s;
  s.index = k;
  s.t = loading.t[static_cast<std::size_t>(k - 1)];
  const double t = s.t;
  const bool proportional = loading.proportional();
  Eigen::VectorXd b;
  double kappa = 0.0;
  Eigen::VectorXd c_raw;
  if (full)
    posed_load(s, &b);
  else
    c_raw = step_load(s, &b, &kappa);
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(step.size());
  for (int i = 0; i < n1; ++i)
    for (const int kt : tangential_coordinates(i))
      if (kt >= 0) shift(kt) = tau_prev(kt);
  const Eigen::VectorXd& origin = cond->origin();
  if (!full) step.c = c_raw - step.S * (origin + shift);
  const bool unloaded = !has_tangential && (shares ? shares->load_is_zero()
                                            : full ? cond->rotated_load().isZero(0.0) : c_raw.isZero(0.0));
  minimize_step(s, shift, origin, unloaded);
  if (!through.empty()) {
    s.status = MinimizerStatus::failed;
    s.message = through;
  }

  // the change against the previous step, and what the step before predicted
  const Eigen::VectorXd x = s.a;
  s.change = (x - x_prev).cwiseAbs().maxCoeff();
  const double floor = options.minimizer.tolerance * std::max({x.cwiseAbs().maxCoeff(), x_prev.cwiseAbs().maxCoeff(),
                                                                std::numeric_limits<double>::min()});
  if (k > 1) {
    const double predicted = change_prev * (t - t_prev) / (t_prev - t_before);
    s.jump = s.change > options.jump_factor * std::max(predicted, floor);
  }
  t_before = t_prev;
  t_prev = t;
  change_prev = s.change;
  x_prev = x;

  // the displacement: the frames, the last step, and every step whose forces (a bilateral
  // node's) or energy (a load outside the span of those kept) need it
  const bool last = k == static_cast<int>(loading.t.size());
  const bool frame = last || (options.frame && options.frame(k));
  Eigen::VectorXd u;
  if (full) {
    if (!shares || frame) u = displacement();  // the point found: no solve
  } else if (frame || any_bilateral || std::isnan(kappa)) {
    const auto t0 = Clock::now();
    make_load_current(&b);
    u = cond->back_substitute(x - origin);
    timings["frames"] += since(t0);
  }
  describe_step(s, last_result, shift, c_raw, kappa, u.size() > 0 ? &u : nullptr, u.size() > 0 ? &b : nullptr);
  if (frame) {
    s.u = u;
    const auto at_t = proportional ? scaled(problem.elasticity, t) : problem.elasticity;
    // across processes each sums its own vertices: exact on its piece of the mesh
    s.forces = shares ? shares->balance(at_t, u, s.contact) : contact_force_balance<dim>(at_t, u, s.contact);
  }
  for (int i = 0; i < n1; ++i)
    for (const int kt : tangential_coordinates(i))
      if (kt >= 0) tau_prev(kt) = x(kt);
  last_shift = shift;
  s.seconds = since(t_start);
  return s;
}

// The first bound of the step at t: extrapolated linearly in t from the last two steps' (the
// mismatch the fixed point starts from is then of the order of the increment squared rather
// than the increment), never below 0; the last step's alone at the second step.
template <int dim>
void BasicPathSolver<dim>::Impl::extrapolate_bound(double t) {
  if (g_before.size() != g.size() || !(t_prev > t_before)) {
    g_before = g;
    return;
  }
  const double r = (t - t_prev) / (t_prev - t_before);
  const Eigen::VectorXd last = g;
  g = (g + r * (g - g_before)).cwiseMax(0.0);
  g_before = last;
}

// A step without a friction bound that depends on the normal contact: one minimization.
template <int dim>
void BasicPathSolver<dim>::Impl::minimize_alone(Step& s, const Eigen::VectorXd& from, const Eigen::VectorXd& origin) {
  MinimizerResult m = minimize_once(from, origin);
  s.status = m.status;
  s.message = m.message;
  s.certificate = m.certificate;
  s.iterations = m.iterations;
  s.may_be_nonunique = m.may_be_nonunique;
  s.a = m.a + origin;
  last_result = std::move(m);
}

// One minimization, or the fixed point on the friction bound: each iterate a Tresca problem with
// the bound g (the tangential weights w_i g_i), until the coupled certificate holds.
template <int dim>
void BasicPathSolver<dim>::Impl::minimize_step(Step& s, const Eigen::VectorXd& shift, const Eigen::VectorXd& origin,
                                     bool unloaded) {
  // from the previous step; a frictionless step whose load vanishes exactly starts from the
  // unloaded state x = 0 (a warm start would shrink towards it by round-off without reaching it)
  const Eigen::VectorXd coordinates_origin = origin + shift;
  const Eigen::VectorXd start = unloaded ? Eigen::VectorXd(-origin) : Eigen::VectorXd(x_prev - coordinates_origin);
  if (full && unloaded) xt.setZero();
  if (s.index > 1 && !check_existence_each_step) options.minimizer.check_existence = false;
  if (!bounded) return minimize_alone(s, start, coordinates_origin);
  extrapolate_bound(s.t);
  FixedPointReport& fp = s.fixed_point;
  fp.used = true;
  fp.relaxation = options.fixed_point.relaxation;
  Eigen::VectorXd from = start;
  detail::AndersonMixing mixing(options.fixed_point.anderson_depth);
  double change_before = std::numeric_limits<double>::infinity();
  int growing = 0;
  // the nodes whose bound depends on the normal contact, and their weights
  std::vector<int> nodes;
  for (int i = 0; i < n1; ++i)
    if (bound_law[static_cast<std::size_t>(i)]) nodes.push_back(i);
  const auto nb = static_cast<Eigen::Index>(nodes.size());
  Eigen::VectorXd weights(nb), used(nb);
  for (Eigen::Index j = 0; j < nb; ++j) weights(j) = boundary.weights(nodes[static_cast<std::size_t>(j)]);
  for (int it = 1; it <= options.fixed_point.max_iterations; ++it) {
    set_bound_weights(nodes);
    MinimizerResult m = minimize_once(from, coordinates_origin);
    fp.iterations = it;
    s.iterations += m.iterations;
    s.may_be_nonunique = m.may_be_nonunique;
    // the bound the solution implies (g elsewhere: no mismatch where the bound is a number)
    Eigen::VectorXd implied = g;
    const bool forces = m.law_force.size() == m.a.size() && m.reaction.size() == m.a.size();
    for (int i : nodes) {
      const int kn = cond->normal_coordinate(i);
      const double force = forces ? m.law_force(kn) + m.reaction(kn) : std::numeric_limits<double>::quiet_NaN();
      implied(i) = bound_law[static_cast<std::size_t>(i)]->bound(m.a(kn) + origin(kn), force / boundary.weights(i));
    }
    Eigen::VectorXd implied_b(nb);
    for (Eigen::Index j = 0; j < nb; ++j) {
      used(j) = g(nodes[static_cast<std::size_t>(j)]);
      implied_b(j) = implied(nodes[static_cast<std::size_t>(j)]);
    }
    const double size = implied_b.cwiseAbs().maxCoeff();
    const double diff = (implied_b - used).cwiseAbs().maxCoeff();
    fp.change = diff == 0.0 ? 0.0 : diff / std::max(size, std::numeric_limits<double>::min());
    s.certificate = friction_bound_certificate(m.certificate, weights, used, implied_b);
    s.status = m.status;
    s.message = m.message;
    s.a = m.a + coordinates_origin;
    fp.converged = m.converged() && s.certificate.converged();
    const bool failed = !m.converged();
    last_result = std::move(m);
    if (fp.converged || failed) break;
    growing = fp.change > change_before ? growing + 1 : 0;
    if (growing > 0) mixing.restart();
    if (growing >= 2 && fp.relaxation > 1.0 / 64.0) {
      fp.relaxation /= 2.0;
      growing = 0;
    }
    change_before = fp.change;
    // the next bound: Anderson's mixing of the last iterates (the relaxed step without
    // history), never below 0
    const Eigen::VectorXd next = mixing.next(used, implied_b - used, fp.relaxation);
    for (Eigen::Index j = 0; j < nb; ++j) g(nodes[static_cast<std::size_t>(j)]) = std::max(0.0, next(j));
    from = last_result.a;
  }
  if (s.status == MinimizerStatus::converged && !fp.converged) {
    s.status = MinimizerStatus::failed;
    s.message = "the fixed point on the friction bound did not converge in " + std::to_string(fp.iterations) +
                " iterations (last relative change of the bound " + shortest(fp.change) + ", relaxation " +
                shortest(fp.relaxation) + "); the friction coefficient may be too large for it to contract";
  }
}

// The step's contact nodes, resultant, zone and energy, from the minimizer's point (and the
// displacement where it was computed).
template <int dim>
void BasicPathSolver<dim>::Impl::describe_step(Step& s, const MinimizerResult& m, const Eigen::VectorXd& shift,
                                     const Eigen::VectorXd& c_raw, double kappa, const Eigen::VectorXd* u,
                                     const Eigen::VectorXd* b) {
  MinimizerResult raw;  // the point in the condensation's coordinates (u_tau total) and its forces
  raw.a = m.a + shift;
  raw.law_force = m.law_force;
  raw.reaction = m.reaction;
  Eigen::VectorXd residual;
  if (shares) {  // across processes: the point's own, gathered where a node reads it (the frames are orthogonal)
    if (shares->contact_reads_residual())
      residual = cond->unrotated_free(shares->distribution().all_gather(shares_residual));
    s.energy = shares_quadratic;
  } else if (u && b) {
    const Eigen::VectorXd uf = dofs->free_part(*u);
    // on the full-space route the rotated matrix stands for one body's, which the posing gave up
    const Eigen::VectorXd Au =
        system->A.rows() == uf.size() ? Eigen::VectorXd(system->A * uf) : cond->unrotated_product(uf);
    residual = Au - *b;
    s.energy = 0.5 * uf.dot(Au) - uf.dot(*b);
  } else {
    const Eigen::VectorXd& x = s.a;
    s.energy = 0.5 * x.dot(step.S * x) - c_raw.dot(x) + kappa;
  }
  s.energy = step.law_energy(m.a, s.energy);
  s.contact.reserve(static_cast<std::size_t>(n1));
  if (has_tangential) {  // NaN at the nodes without friction
    s.slip = Eigen::VectorXd::Constant(n1, std::numeric_limits<double>::quiet_NaN());
    s.friction_bound = s.slip;
  }
  for (int i = 0; i < n1; ++i) {
    auto node = contact_node(*problem.elasticity.mesh, boundary, *cond, *dofs, i, raw,
                                    residual.size() > 0 ? &residual : nullptr);
    if (const int k = cond->tangential_coordinate(i); k >= 0) {
      // the slip of the step: along tau in the plane, its length on a solid's surface
      const int k2 = cond->second_tangential_coordinate(i);
      s.slip(i) = dim == 3 ? std::hypot(m.a(k), k2 >= 0 ? m.a(k2) : 0.0) : m.a(k);
      node.friction_state = friction_state(step.law_of(k), s.slip(i));
      s.friction_bound(i) = step.w(k) / boundary.weights(i) * step.law_of(k).derivative(LawPart::j, 0.0, +1);
    }
    s.contact.push_back(std::move(node));
  }
  s.contact_force = contact_resultant(s.contact);
  s.zone = contact_zone(s.contact);
  if (!std::isfinite(s.energy) && s.converged()) {
    s.status = MinimizerStatus::failed;
    s.message = "the energy of the step is not finite";
  }
}

template <int dim>
auto BasicPathSolver<dim>::Impl::last_solution(const Step& s, const MinimizerResult& m, const Eigen::VectorXd& shift)
    -> BasicContactSolution<dim> {
  BasicContactSolution<dim> sol;
  sol.u = s.u;
  sol.unknowns = dofs->num_free();
  sol.contact = s.contact;
  for (const auto& part : parts) sol.contact_parts.push_back(part.name);
  sol.status = s.status;
  sol.message = s.message;
  sol.certificate = s.certificate;
  sol.may_be_nonunique = s.may_be_nonunique;
  sol.minimizer = m;
  sol.minimizer->a = m.a + shift;
  sol.uniqueness_margin = cond->uniqueness_margin();
  sol.uniqueness_roundoff = cond->reduced().uniqueness_roundoff;
  sol.held_by_contact = held_by_contact;
  sol.energy = s.energy;
  if (s.forces) sol.forces = *s.forces;
  sol.stages = {"assembly", full ? "posing" : "condensation", "path"};
  if (sol.converged() && !sol.u.allFinite()) {
    sol.status = MinimizerStatus::failed;
    sol.message = "the displacement is not finite (NaN or Inf after back-substitution)";
  }
  return sol;
}

template <int dim>
BasicPathSolver<dim>::BasicPathSolver(BasicContactProblem<dim>& problem, std::unique_ptr<SparseFactorization> factorization,
                                      const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading,
                                      BasicPathOptions<dim> options)
    : impl_(std::make_unique<Impl>(problem, std::move(factorization), nullptr, minimizer, std::move(loading),
                                   std::move(options))) {}

template <int dim>
BasicPathSolver<dim>::BasicPathSolver(BasicContactProblem<dim>& problem, std::unique_ptr<KrylovSolver> krylov,
                                      const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading,
                                      BasicPathOptions<dim> options)
    : impl_(std::make_unique<Impl>(problem, nullptr, std::move(krylov), minimizer, std::move(loading),
                                   std::move(options))) {}

template <int dim>
BasicPathSolver<dim>::~BasicPathSolver() = default;

template <int dim>
BasicPathSolution<dim> BasicPathSolver<dim>::run() {
  Impl& p = *impl_;
  if (p.cond) throw InternalError("PathSolver::run is called once");
  const auto start = Clock::now();
  p.set_up();
  BasicPathSolution<dim> out;
  out.proportional = p.loading.proportional();
  const auto t_path = Clock::now();
  const int K = static_cast<int>(p.loading.t.size());
  const SingleThreadedBlas one_thread;  // each step's dense work is small
  std::optional<BasicPathStep<dim>> failed;  // the first step that did not converge (its scalars)
  for (int k = 1; k <= K; ++k) {
    if (!p.options.keep_steps) out.steps.clear();
    out.steps.push_back(p.solve_step(k));
    const BasicPathStep<dim>& step = out.steps.back();
    out.solved_steps += 1;
    out.converged_steps += step.converged() ? 1 : 0;
    out.jump_count += step.jump ? 1 : 0;
    if (!step.converged() && !failed) {
      failed.emplace();
      failed->index = step.index, failed->t = step.t, failed->status = step.status, failed->message = step.message;
    }
    if (p.options.on_step && !p.options.on_step(step)) break;
  }
  p.timings["path"] = since(t_path) - p.timings["frames"];
  out.condensed_loads = p.condensed_loads;
  if (out.steps.back().u.size() == 0) {
    // stopped early by on_step: the displacement of the step it stopped at
    auto& s = out.steps.back();
    if (p.full) {
      s.u = p.displacement();
    } else {
      Eigen::VectorXd b;
      p.make_load_current(&b);
      s.u = p.cond->back_substitute(s.a - p.cond->origin());
    }
    const auto at_t = out.proportional ? scaled(p.problem.elasticity, s.t) : p.problem.elasticity;
    s.forces = p.shares ? p.shares->balance(at_t, s.u, s.contact) : contact_force_balance<dim>(at_t, s.u, s.contact);
  }
  out.last = p.last_solution(out.steps.back(), p.last_result, p.last_shift);
  if (p.full) out.last.full_space = p.full_space_counts;
  carry_first_failure(out, failed);
  p.timings["total"] = since(start);
  out.timings = p.timings;
  out.last.timings = p.timings;
  return out;
}

template <int dim>
BasicPathSolution<dim> solve_path(BasicContactProblem<dim>& problem, std::unique_ptr<SparseFactorization> factorization,
                                  const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading,
                                  BasicPathOptions<dim> options) {
  return BasicPathSolver<dim>(problem, std::move(factorization), minimizer, std::move(loading), std::move(options)).run();
}

template <int dim>
BasicPathSolution<dim> solve_path(BasicContactProblem<dim>& problem, std::unique_ptr<KrylovSolver> krylov,
                                  const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading,
                                  BasicPathOptions<dim> options) {
  return BasicPathSolver<dim>(problem, std::move(krylov), minimizer, std::move(loading), std::move(options)).run();
}

template struct BasicPathSolution<2>;
template struct BasicPathSolution<3>;
template class BasicPathSolver<2>;
template class BasicPathSolver<3>;
template BasicPathSolution<2> solve_path(ContactProblem&, std::unique_ptr<SparseFactorization>, const NonsmoothMinimizer&,
                                         PathLoading, PathOptions);
template BasicPathSolution<3> solve_path(ContactProblem3D&, std::unique_ptr<SparseFactorization>,
                                         const NonsmoothMinimizer&, BasicPathLoading<3>, BasicPathOptions<3>);
template BasicPathSolution<2> solve_path(ContactProblem&, std::unique_ptr<KrylovSolver>, const NonsmoothMinimizer&,
                                         PathLoading, PathOptions);
template BasicPathSolution<3> solve_path(ContactProblem3D&, std::unique_ptr<KrylovSolver>, const NonsmoothMinimizer&,
                                         BasicPathLoading<3>, BasicPathOptions<3>);

}  // namespace hemivem
