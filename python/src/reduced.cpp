// Contact laws, the certificate, the reduced problem (condense), and minimize.
#include "reduced.hpp"

#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <hemivem/support/blas_threads.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/certificate.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/uniqueness.hpp>

namespace hemivem::python {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string number_text(double v) {
  std::ostringstream o;
  o << std::setprecision(6) << v;
  return o.str();
}

/// f applied to a number (a float back) or to an array-like (an array of the same shape back).
template <class F>
py::object map_values(const py::handle& r, F f) {
  if (py::isinstance<py::float_>(r) || py::isinstance<py::int_>(r)) return py::float_(f(r.cast<double>()));
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(r);
  if (!a) throw InputError("expected a number or an array of numbers", "r");
  py::array_t<double> out(std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim()));
  const double* in = a.data();
  double* o = out.mutable_data();
  for (py::ssize_t i = 0; i < a.size(); ++i) o[i] = f(in[i]);
  return out;
}

LawPart part_from(const std::string& part) {
  if (part == "j") return LawPart::j;
  if (part == "j1") return LawPart::j1;
  if (part == "j2") return LawPart::j2;
  throw InputError("unknown part '" + part + "'; expected j, j1 or j2", "part");
}

std::string certificate_repr(const Certificate& c) {
  std::ostringstream o;
  o.precision(3);
  o << std::scientific << "Certificate(primal=" << c.primal << ", dual=" << c.dual << ", tolerance=" << c.tolerance
    << ", converged=" << (c.converged() ? "True" : "False") << ")";
  return o.str();
}

/// A square matrix of finite numbers, symmetric to 1e-12 relative (as read_reduced_problem).
Eigen::MatrixXd matrix_from(const py::handle& values) {
  const auto a = py::array_t<double, py::array::f_style | py::array::forcecast>::ensure(values);
  if (!a || a.ndim() != 2 || a.shape(0) != a.shape(1)) throw InputError("expected a square (n, n) array", "S");
  const Eigen::Index n = a.shape(0);
  Eigen::MatrixXd S = Eigen::Map<const Eigen::MatrixXd>(a.data(), n, n);
  double scale = 0.0;
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!std::isfinite(S(i, j)))
        throw InputError("S[" + std::to_string(i) + ", " + std::to_string(j) + "] = " + std::to_string(S(i, j)) +
                             " is not finite",
                         "S");
      scale = std::max(scale, std::abs(S(i, j)));
    }
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < j; ++i)
      if (std::abs(S(i, j) - S(j, i)) > 1e-12 * scale)
        throw InputError("S is not symmetric: S[" + std::to_string(i) + ", " + std::to_string(j) + "] - S[" +
                             std::to_string(j) + ", " + std::to_string(i) + "] = " + std::to_string(S(i, j) - S(j, i)),
                         "S");
  return S;
}

std::shared_ptr<const ContactLaw> law_from(const py::handle& law) {
  if (py::isinstance<PyLaw>(law)) return law.cast<const PyLaw&>().law;
  if (py::isinstance<py::str>(law)) return make_contact_law(law.cast<std::string>());
  throw InputError("expected a ContactLaw or the name of a shipped law", "law");
}

/// The named numbers of engine parameters given as keyword arguments.
std::map<std::string, double> parameters_from(const py::kwargs& kwargs) {
  std::map<std::string, double> out;
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    if (!(py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)))
      throw InputError("engine parameter '" + name + "' must be a number, got " +
                           py::str(value.get_type().attr("__name__")).cast<std::string>(),
                       name);
    out[name] = value.cast<double>();
  }
  return out;
}

using ReducedClass = py::class_<ReducedHolder, std::shared_ptr<ReducedHolder>>;

/// The name of the constraint of a uniform problem, "coordinate-wise" otherwise.
std::string constraint_name(const ReducedProblem& p) {
  const std::optional<UniformForm> u = p.uniform_form();
  return u ? to_string(u->constraint) : std::string("coordinate-wise");
}

/// Certificate and CertifiedPoint.
void register_certificate(py::module_& m) {
  py::class_<Certificate>(m, "Certificate", R"doc(
The certificate of a point of the reduced problem (docs/reference/certificate.md): primal = ||dist(a, C)||_inf / l
and dual = ||S a - c + zeta + lambda||_inf / f, dimensionless; converged when both are <= the
tolerance. One implementation for every engine, the command and Python.
)doc")
      .def_readonly("primal", &Certificate::primal)
      .def_readonly("dual", &Certificate::dual)
      .def_readonly("length_scale", &Certificate::length_scale)
      .def_readonly("force_scale", &Certificate::force_scale)
      .def_readonly("tolerance", &Certificate::tolerance)
      .def_property_readonly("converged", &Certificate::converged)
      .def_property_readonly("worst", &Certificate::worst, "max(primal, dual).")
      .def("__repr__", &certificate_repr);

  py::class_<CertifiedPoint, std::shared_ptr<CertifiedPoint>>(m, "CertifiedPoint",
                                                               "A point with its certificate and the forces it found.")
      .def_property_readonly("a", [](py::object s) { auto& p = s.cast<CertifiedPoint&>(); return view(p.a.data(), p.a.size(), s); },
                             "The snapped point that is certified.")
      .def_property_readonly("law_force", [](py::object s) { auto& p = s.cast<CertifiedPoint&>(); return view(p.law_force.data(), p.law_force.size(), s); },
                             "zeta_i in w_i dj(a_i).")
      .def_property_readonly("reaction", [](py::object s) { auto& p = s.cast<CertifiedPoint&>(); return view(p.reaction.data(), p.reaction.size(), s); },
                             "lambda_i, the reaction of the constraint.")
      .def_readonly("certificate", &CertifiedPoint::certificate)
      .def_property_readonly("converged", [](const CertifiedPoint& p) { return p.certificate.converged(); })
      .def("__repr__", [](const CertifiedPoint& p) { return "CertifiedPoint(" + certificate_repr(p.certificate) + ")"; });
}

/// Iteration, what a callback sees.
void register_iteration(py::module_& m) {
  py::class_<IterationRecord>(m, "Iteration", "One iteration of a minimizer, as given to a callback.")
      .def_readonly("iteration", &IterationRecord::iteration)
      .def_readonly("objective", &IterationRecord::objective, "F at the current point.")
      .def_readonly("primal", &IterationRecord::primal)
      .def_readonly("dual", &IterationRecord::dual)
      .def_readonly("active", &IterationRecord::active, "Coordinates at a bound.")
      .def_readonly("seconds", &IterationRecord::seconds)
      .def("__repr__", [](const IterationRecord& r) {
        std::ostringstream o;
        o << "Iteration(" << r.iteration << ", objective=" << r.objective << ", primal=" << r.primal << ", dual=" << r.dual
          << ", active=" << r.active << ")";
        return o.str();
      });
}

/// CriticalPoint, of a global search.
void register_critical_point(py::module_& m) {
  py::class_<PyCriticalPoint>(m, "CriticalPoint", R"doc(
A certified critical point found by a global search (search="global"): the point a (a
read-only view), F(a) as reduced_objective, the potential energy of the body (a solve only;
None for a reduced problem alone), its certificate, how many local runs reached it and the
engines that did. The same numbers as result.json's "critical_points".
)doc")
      .def_property_readonly("a", [](py::object s) {
             const CriticalPoint& p = *s.cast<const PyCriticalPoint&>().point;
             return view(p.a.data(), p.a.size(), s);
           }, "The point (the contact unknowns), float64, a read-only view.")
      .def_property_readonly("reduced_objective", [](const PyCriticalPoint& p) { return p.point->objective; }, "F(a).")
      .def_property_readonly("potential_energy", [](const PyCriticalPoint& p) -> std::optional<double> {
             if (!p.shift) return std::nullopt;
             return p.point->objective + *p.shift;
           }, "The potential energy of the displacement of a (None for a reduced problem alone).")
      .def_property_readonly("certificate", [](const PyCriticalPoint& p) { return p.point->certificate; })
      .def_property_readonly("starts", [](const PyCriticalPoint& p) { return p.point->starts; },
                             "The local runs that reached this point.")
      .def_property_readonly("engines", [](const PyCriticalPoint& p) { return p.point->engines; },
                             "The engines that reached it, in the order they first did.")
      .def("__repr__", [](const PyCriticalPoint& p) {
        std::ostringstream o;
        o << std::setprecision(10) << "CriticalPoint(reduced_objective=" << p.point->objective;
        if (p.shift) o << ", potential_energy=" << p.point->objective + *p.shift;
        o << ", starts=" << p.point->starts << ", engines=" << py::repr(py::cast(p.point->engines)).cast<std::string>()
          << ")";
        return o.str();
      });
}

/// SearchProgress, one local run of a global search.
void register_search_progress(py::module_& m) {
  py::class_<GlobalSearchProgress>(m, "SearchProgress", R"doc(
One local run of a global search, as given to progress= of solve and minimize (the lines
`hemivem solve --global` prints on stderr).
)doc")
      .def_readonly("run", &GlobalSearchProgress::run, "1, 2, ... (local runs so far).")
      .def_readonly("max_runs", &GlobalSearchProgress::max_runs, "The budget (max_starts).")
      .def_readonly("engine", &GlobalSearchProgress::engine, "The engine of this run.")
      .def_readonly("start", &GlobalSearchProgress::start,
                    "The start's name ('quadratic minimizer', 'breakpoint 0.01', 'random 3', 'move 2 -> 0.005' ...).")
      .def_readonly("certified", &GlobalSearchProgress::certified)
      .def_readonly("objective", &GlobalSearchProgress::objective, "F at the run's point.")
      .def_readonly("lowest", &GlobalSearchProgress::lowest, "The lowest F of a certified point so far (NaN: none yet).")
      .def_readonly("critical_points", &GlobalSearchProgress::critical_points, "Distinct certified critical points so far.")
      .def_readonly("seconds", &GlobalSearchProgress::seconds, "Since the search began.")
      .def("__repr__", [](const GlobalSearchProgress& g) {
        std::ostringstream o;
        o << std::setprecision(10) << "SearchProgress(run=" << g.run << "/" << g.max_runs
          << ", engine=" << py::repr(py::str(g.engine)).cast<std::string>()
          << ", start=" << py::repr(py::str(g.start)).cast<std::string>() << ", objective=" << g.objective
          << ", certified=" << (g.certified ? "True" : "False") << ", lowest=" << g.lowest << ")";
        return o.str();
      });
}

/// MinimizerResult.
void register_minimizer_result(py::module_& m) {
  py::class_<MinimizerResult, std::shared_ptr<MinimizerResult>>(m, "MinimizerResult", R"doc(
What a minimizer returns: status (decided by the certificate alone), the point a with the law
force and reaction of its certificate, F(a), counts, the per-iteration history and timings.
)doc")
      .def_property_readonly("status", [](const MinimizerResult& r) { return to_string(r.status); },
                             "'converged', 'iteration limit', 'evaluation limit', 'stalled', "
                             "'stopped by callback', 'failed' or 'unbounded' (no solution: F is unbounded below).")
      .def_property_readonly("converged", &MinimizerResult::converged)
      .def_readonly("message", &MinimizerResult::message)
      .def_property_readonly("a", [](py::object s) { auto& r = s.cast<MinimizerResult&>(); return view(r.a.data(), r.a.size(), s); })
      .def_property_readonly("law_force", [](py::object s) { auto& r = s.cast<MinimizerResult&>(); return view(r.law_force.data(), r.law_force.size(), s); })
      .def_property_readonly("reaction", [](py::object s) { auto& r = s.cast<MinimizerResult&>(); return view(r.reaction.data(), r.reaction.size(), s); })
      .def_readonly("objective", &MinimizerResult::objective, "F(a).")
      .def_readonly("certificate", &MinimizerResult::certificate)
      .def_readonly("iterations", &MinimizerResult::iterations)
      .def_readonly("function_evaluations", &MinimizerResult::function_evaluations)
      .def_readonly("subgradient_evaluations", &MinimizerResult::subgradient_evaluations)
      .def_readonly("timings", &MinimizerResult::timings)
      .def_readonly("may_be_nonunique", &MinimizerResult::may_be_nonunique)
      .def_property_readonly("history", [](const MinimizerResult& r) { return history_dict(r.history); },
                             "Per iteration (per local run of a global search): dict of arrays iteration,\n"
                             "reduced_objective, primal, dual, active, seconds.")
      .def_property_readonly(
          "critical_points",
          [](py::object s) {
            const auto r = s.cast<std::shared_ptr<MinimizerResult>>();
            return critical_points_list(r, *r, std::nullopt);
          },
          "A global search's distinct certified critical points (CriticalPoint), lowest F first (the\n"
          "point returned is the first); empty for a local engine.")
      .def("__repr__", [](const MinimizerResult& r) {
        std::ostringstream o;
        o << "MinimizerResult(status=" << py::repr(py::str(to_string(r.status))).cast<std::string>()
          << ", objective=" << r.objective << ", iterations=" << r.iterations << ", " << certificate_repr(r.certificate)
          << ")";
        return o.str();
      });
}

/// The class ReducedProblem with its constructors (arrays, files) and write().
ReducedClass register_reduced_problem(py::module_& m) {
  ReducedClass cls(m, "ReducedProblem", R"doc(
The reduced (condensed) contact problem (docs/reference/certificate.md):

    min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j(a_i)   s.t.  lower <= a <= upper

From hemivem.condense(scene) (which keeps the factorization, so back_substitute(a) gives the
displacement), from Result.reduced, from files (ReducedProblem.read, the format of
`hemivem solve --export-reduced DIR`), or from arrays:

    p = hemivem.ReducedProblem(S, c, w, g, law="paper", constraint="box")

S is an (n, n) float64 read-only view in Fortran (column) order; c and w are 1-D views (g,
lower and upper are copies). The views stay valid as long as any of them, or the problem, is
referenced.
)doc");
  cls.def(py::init([](py::handle S, py::handle c, py::handle w, py::object g, py::handle law, const std::string& constraint,
                       std::optional<double> margin) {
             auto h = std::make_shared<ReducedHolder>();
             Eigen::MatrixXd matrix = matrix_from(S);
             Eigen::VectorXd cv = vector_from(c, "c"), wv = vector_from(w, "w");
             const ConstraintKind kind = constraint_kind_from_string(constraint);
             const Eigen::VectorXd gv = g.is_none() ? Eigen::VectorXd() : vector_from(g, "g");
             for (Eigen::Index i = 0; i < wv.size(); ++i)
               if (!(wv(i) > 0.0)) throw InputError("w[" + std::to_string(i) + "] = " + std::to_string(wv(i)) + " must be > 0", "w");
             for (Eigen::Index i = 0; i < gv.size(); ++i)
               if (!(gv(i) >= 0.0)) throw InputError("g[" + std::to_string(i) + "] = " + std::to_string(gv(i)) + " must be >= 0", "g");
             ReducedProblem& p = h->own;
             p = ReducedProblem::uniform(std::move(matrix), std::move(cv), std::move(wv), law_from(law), kind, gv);
             check_sizes(p, "ReducedProblem");
             const UniquenessMargin m = measure_uniqueness(p);
             if (margin && !margin_agrees(*margin, m))
               throw InputError("given as " + number_text(*margin) + " but lambda_min(S - alpha_j W) = " +
                                    number_text(m.margin) + " (round-off bound " + number_text(m.roundoff) +
                                    "): a margin is computed, leave it out",
                                "uniqueness_margin");
             p.uniqueness_margin = m.margin;
             p.uniqueness_roundoff = m.roundoff;
             return h;
           }),
           py::arg("S"), py::arg("c"), py::arg("w"), py::arg("g") = py::none(), py::kw_only(), py::arg("law") = "paper",
           py::arg("constraint") = "box", py::arg("uniqueness_margin") = py::none(),
           "A reduced problem from arrays: S (n, n) symmetric, c, w > 0, g >= 0 (needed by the\n"
           "box and one-sided constraints), a law (name or ContactLaw), constraint 'box',\n"
           "'one-sided' or 'none'. InputError naming the array and index of a non-finite entry.\n"
           "The uniqueness margin lambda_min(S - alpha_j W) is always computed (0 within round-off);\n"
           "a uniqueness_margin given that disagrees with it is an InputError.")
      .def_static(
          "read",
          [](const std::filesystem::path& folder, py::object law) {
            auto h = std::make_shared<ReducedHolder>();
            h->own = read_reduced_problem(folder, law.is_none() ? nullptr : law_from(law));
            return h;
          },
          py::arg("folder"), py::arg("law") = py::none(),
          "Reads a folder written by `hemivem solve --export-reduced DIR` or ReducedProblem.write\n"
          "(`law` replaces law.txt). InputError naming file and line of any defect.")
      .def("write", [](const ReducedHolder& h, const std::filesystem::path& folder) { write_reduced_problem(folder, h.problem()); },
           py::arg("folder"), "Writes the folder format of --export-reduced (S.mtx, c.txt, w.txt, g.txt, law.txt, problem.txt).");
  return cls;
}

/// The arrays and numbers of a ReducedProblem.
void define_reduced_arrays(ReducedClass& cls) {
  cls.def_property_readonly("S", [](py::object s) {
             const auto& p = s.cast<const ReducedHolder&>().problem();
             return view(p.S.data(), p.S.rows(), p.S.cols(), s, false);
           }, "(n, n) float64, Fortran order, read-only view.")
      .def_property_readonly("c", [](py::object s) { const auto& p = s.cast<const ReducedHolder&>().problem(); return view(p.c.data(), p.c.size(), s); })
      .def_property_readonly("w", [](py::object s) { const auto& p = s.cast<const ReducedHolder&>().problem(); return view(p.w.data(), p.w.size(), s); },
                             "Nodal weights w_i (the length of boundary each node stands for).")
      .def_property_readonly("g", [](const ReducedHolder& h) {
             const std::optional<UniformForm> u = h.problem().uniform_form();
             return copy(u ? u->g : Eigen::VectorXd());
           }, "Gaps g_i of the one constraint (zero without one; empty in the coordinate-wise form).")
      .def_property_readonly("lower", [](const ReducedHolder& h) {
             const auto& p = h.problem();
             Eigen::VectorXd v(p.size());
             for (Eigen::Index i = 0; i < p.size(); ++i) v(i) = p.lower(i);
             return copy(v);
           }, "Lower bounds of a (-inf where there is none).")
      .def_property_readonly("upper", [](const ReducedHolder& h) {
             const auto& p = h.problem();
             Eigen::VectorXd v(p.size());
             for (Eigen::Index i = 0; i < p.size(); ++i) v(i) = p.upper(i);
             return copy(v);
           }, "Upper bounds of a (inf where there is none).")
      .def_property_readonly("law", [](const ReducedHolder& h) { return PyLaw{h.problem().laws.front()}; }, "Law 0.")
      .def_property_readonly("laws", [](const ReducedHolder& h) {
             std::vector<PyLaw> out;
             for (const auto& law : h.problem().laws) out.push_back(PyLaw{law});
             return out;
           }, "Every law (more than one in the coordinate-wise form of friction).")
      .def_property_readonly("constraint", [](const ReducedHolder& h) { return constraint_name(h.problem()); })
      .def_property_readonly("coordinatewise", [](const ReducedHolder& h) { return h.problem().coordinatewise(); })
      .def_property_readonly("uniqueness_margin", [](const ReducedHolder& h) { return h.problem().uniqueness_margin; },
                             "lambda_min(S - diag(alpha_i w_i)), exactly 0 within round-off: the critical point\n"
                             "is unique when positive; 0 means F is convex but not strongly convex along some\n"
                             "direction (uniqueness not proved).")
      .def_property_readonly("uniqueness_roundoff", [](const ReducedHolder& h) { return h.problem().uniqueness_roundoff; },
                             "The round-off bound of uniqueness_margin: n eps (||S||_1 + max |alpha_i w_i|).")
      .def_property_readonly("uniqueness", [](const ReducedHolder& h) { return uniqueness_verdict(h.problem().uniqueness_margin); },
                             "'unique', 'zero', 'negative' or 'unknown' (the margin's verdict).")
      .def_property_readonly("size", [](const ReducedHolder& h) { return h.problem().size(); })
      .def("__len__", [](const ReducedHolder& h) { return h.problem().size(); });
}

/// Where a ReducedProblem came from (condense() only).
void define_reduced_origin(ReducedClass& cls) {
  cls.def_property_readonly("linear", [](const ReducedHolder& h) { return h.linear; },
                             "The linear engine of the condensation ('' when not condensed here).")
      .def_property_readonly("timings", [](const ReducedHolder& h) { return h.timings; },
                             "Seconds of mesh, assembly and condensation (condense() only).")
      .def_property_readonly("mesh", [](const ReducedHolder& h) -> py::object {
             if (!h.built) return py::none();
             return py::cast(PyMesh{std::shared_ptr<const Mesh>(h.self.lock(), &h.built->mesh)});
           }, "The mesh of the condensed scene (None for a problem read from files or arrays).")
      .def_property_readonly("contact_vertices", [](const ReducedHolder& h) -> py::object {
             if (!h.condensation) return py::none();
             return copy(std::vector<std::int32_t>(h.boundary.nodes.begin(), h.boundary.nodes.end()));
           }, "The mesh vertex of each contact node (condense() only).");
}

/// F, the projection onto C and the certificate of a point.
void define_reduced_methods(ReducedClass& cls) {
  cls.def(
          "energy", [](const ReducedHolder& h, py::handle a) {
            const auto& p = h.problem();
            const Eigen::VectorXd x = vector_from(a, "a");
            if (x.size() != p.size())
              throw InputError("a has size " + std::to_string(x.size()) + ", the problem " + std::to_string(p.size()), "a");
            return p.energy(x);
          },
          py::arg("a"), "F(a).")
      .def(
          "project", [](const ReducedHolder& h, py::handle a) {
            const auto& p = h.problem();
            const Eigen::VectorXd x = vector_from(a, "a");
            if (x.size() != p.size())
              throw InputError("a has size " + std::to_string(x.size()) + ", the problem " + std::to_string(p.size()), "a");
            return copy(p.project(x));
          },
          py::arg("a"), "The projection of a onto the constraint set C.")
      .def(
          "certify",
          [](const ReducedHolder& h, py::handle a, double tolerance) {
            const Eigen::VectorXd x = vector_from(a, "a", false);
            return std::make_shared<CertifiedPoint>(certify(h.problem(), x, tolerance));
          },
          py::arg("a"), py::arg("tolerance") = 1e-10,
          "The certificate of a point a (hemivem::certify, the one implementation every engine\n"
          "is judged by) with the snapped point and the forces it found. A point of the wrong\n"
          "size or with a non-finite entry gets infinite residuals.")
      .def(
          "certificate",
          [](const ReducedHolder& h, py::handle a, double tolerance) {
            return certificate(h.problem(), vector_from(a, "a", false), tolerance);
          },
          py::arg("a"), py::arg("tolerance") = 1e-10, "The numbers of certify(a).");
}

/// The displacement of the body for contact unknowns (condense() only), and the repr.
void define_back_substitute(ReducedClass& cls) {
  cls.def(
          "back_substitute",
          [](const ReducedHolder& h, py::handle a) {
            if (!h.condensation)
              throw InputError("this reduced problem has no factorization (it was read from files, made from arrays or "
                               "copied from a Result); use hemivem.condense(scene)",
                               "back_substitute");
            const auto& p = h.problem();
            const Eigen::VectorXd x = vector_from(a, "a");
            if (x.size() != p.size())
              throw InputError("a has size " + std::to_string(x.size()) + ", the problem " + std::to_string(p.size()), "a");
            Eigen::VectorXd u;
            {
              py::gil_scoped_release release;
              const SingleThreadedRun one_thread;
              u = h.condensation->back_substitute(x);
            }
            py::array_t<double> out({u.size() / 2, Eigen::Index(2)});
            std::copy(u.data(), u.data() + u.size(), out.mutable_data());
            return out;
          },
          py::arg("a"),
          "The displacement (num_vertices, 2) of the whole body for the contact unknowns a:\n"
          "u2 = A22^-1 (b2 - A21 a) with the factorization kept by condense().")
      .def("__repr__", [](const ReducedHolder& h) {
        const auto& p = h.problem();
        std::ostringstream o;
        o << "ReducedProblem(size=" << p.size()
          << ", law=" << py::repr(py::str(p.laws.empty() ? "" : p.laws.front()->name())).cast<std::string>()
          << ", constraint=" << py::repr(py::str(constraint_name(p))).cast<std::string>()
          << ", uniqueness_margin=" << p.uniqueness_margin << (h.condensation ? ", linear=" + h.linear : std::string()) << ")";
        return o.str();
      });
}

/// condense(scene).
void register_condense(py::module_& m) {
  m.def(
      "condense",
      [](const Scene& scene_in, std::optional<std::string> linear) {
        Scene scene = scene_in;
        if (scene.dimension() == 3)
          throw InputError("hemivem.condense takes two-dimensional scenes; a three-dimensional scene's reduced "
                           "problem is Result.reduced of hemivem.solve(scene) (without a factorization to "
                           "back-substitute)",
                           scene.where("mesh"));
        if (linear) apply_override(scene, "solver.linear=" + toml_string(*linear));
        FactorizationOptions fo;
        fo.engine = scene.solver.linear;
        check_linear_engine(fo.engine, linear ? "linear" : scene.where("solver.linear"));
        auto factorization = make_factorization(fo);
        auto h = std::make_shared<ReducedHolder>();
        h->self = h;
        h->linear = factorization->name();
        SignalWatch watch;
        try {
          py::gil_scoped_release release;
          const SingleThreadedRun one_thread;  // as every solve (docs/performance.md, "Threads")
          auto t = Clock::now();
          h->built = build_problem(scene);
          h->timings["mesh"] = since(t);
          if (watch.poll()) throw Interrupted{};
          const ContactProblem& problem = h->built->problem;
          t = Clock::now();
          const LinearSystem system = assemble(problem.elasticity);
          h->timings["assembly"] = since(t);
          h->boundary = contact_boundary(problem, system.dofs);
          if (h->boundary.size() == 0)
            throw InputError("the scene has no contact boundary: there is no reduced problem", scene.where("contact"));
          const std::vector<ContactPart> parts = contact_parts(problem);
          for (const ContactPart& part : parts)
            if (!part.law) throw InputError("the contact boundary has no contact law", scene.where("contact"));
          if (watch.poll()) throw Interrupted{};
          t = Clock::now();
          h->condensation = std::make_unique<Condensation>(system, h->boundary, std::move(factorization),
                                                           part_conditions(parts));
          h->timings["condensation"] = since(t);
        } catch (const Interrupted&) {
        }
        watch.raise_if_interrupted();
        return h;
      },
      py::arg("scene"), py::kw_only(), py::arg("linear") = py::none(),
      "Builds the scene's problem, assembles it and condenses it onto the contact unknowns with\n"
      "the linear engine (default: the scene's solver.linear; 'auto' is the fastest built).\n"
      "Returns a ReducedProblem that keeps the factorization for back_substitute(a).\n"
      "Runs without the GIL; Ctrl-C is honoured between stages.");
}

/// minimize(reduced, ...) of the module.
std::shared_ptr<MinimizerResult> minimize_reduced(std::shared_ptr<ReducedHolder> reduced, const std::string& minimizer,
                                                  py::object start, double tolerance, int max_iterations,
                                                  int max_evaluations, py::object callback, const std::string& search,
                                                  std::optional<int> max_starts, std::optional<double> time_budget,
                                                  std::optional<int> seed, std::optional<std::vector<std::string>> engines,
                                                  py::object progress, const py::kwargs& kwargs) {
  std::unique_ptr<NonsmoothMinimizer> engine = make_minimizer(minimizer, parameters_from(kwargs));
  const bool global = is_global_search(search, "search");
  if (!global)
    refuse_global_keywords({{"max_starts", max_starts.has_value()},
                            {"time_budget", time_budget.has_value()},
                            {"seed", seed.has_value()},
                            {"engines", engines.has_value()}},
                           "search='" + search + "'");
  GlobalSearchOptions go;
  if (max_starts) go.max_starts = *max_starts;
  if (time_budget) go.time_budget = *time_budget;
  if (seed) go.seed = *seed;
  require_valid(go, "global search");
  if (global && !callback.is_none())
    throw InputError("a global search reports its local runs to progress=, not iterations to a callback", "callback");
  if (!global && !progress.is_none())
    throw InputError("only a global search (search='global') reports local runs; a callback sees iterations",
                     "progress");
  const ReducedProblem& p = reduced->problem();
  Eigen::VectorXd a0;
  if (!start.is_none()) a0 = vector_from(start, "start");
  check_tolerance(tolerance, "tolerance");
  MinimizerOptions o;
  o.tolerance = tolerance;
  o.max_iterations = max_iterations;
  o.max_evaluations = max_evaluations;
  SignalWatch watch;
  o.callback = [&](const IterationRecord& r) {
    if (watch.poll()) return false;
    if (callback.is_none()) return true;
    py::gil_scoped_acquire gil;
    try {
      const py::object verdict = callback(r);
      return verdict.is_none() || verdict.cast<bool>();
    } catch (py::error_already_set& e) {
      e.restore();
      watch.keep_current_error();
      return false;
    }
  };
  if (global) {
    go.progress = search_progress(watch, progress);
    engine = make_global_search(std::move(engine), std::move(go), engines.value_or(std::vector<std::string>{}));
  }
  auto result = std::make_shared<MinimizerResult>();
  try {
    py::gil_scoped_release release;
    *result = engine->minimize(p, a0, o);
  } catch (const Interrupted&) {
  }
  watch.raise_if_interrupted();
  return result;
}

/// minimize(reduced, ...).
void register_minimize(py::module_& m) {
  m.def(
      "minimize",
      &minimize_reduced,
      py::arg("reduced"), py::arg("minimizer") = "ssn", py::kw_only(), py::arg("start") = py::none(),
      py::arg("tolerance") = 1e-10, py::arg("max_iterations") = 1000, py::arg("max_evaluations") = 1000000,
      py::arg("callback") = py::none(), py::arg("search") = "local", py::arg("max_starts") = py::none(),
      py::arg("time_budget") = py::none(), py::arg("seed") = py::none(),
      py::arg("engines") = py::none(), py::arg("progress") = py::none(),
      R"doc(Minimizes F over C with a minimizer (available_engines()['minimizer']) from `start`
(projected onto C; default zero). Further keyword arguments are the engine's parameters,
checked as in a scene's [solver.parameters] (InputError naming the engine and the field).
callback(Iteration) after every iteration may return False to stop the run.

search="global" (as `hemivem minimize --global`) looks for the lowest of several critical
points: local runs of every built minimizer, `minimizer` first, from deterministic and
seeded random starts, then single-coordinate moves; at most max_starts local runs, none
begun after time_budget seconds, random starts drawn with `seed`; `engines` names the engines
that run besides `minimizer` (as `--engines`; default every built one). The result is the lowest
certified critical point; result.critical_points lists every one found (CriticalPoint).
max_starts, time_budget, seed and engines default to 64, 60 s, 1 and every built minimizer;
given with a local search they are an InputError naming them (they would have no effect).
progress(SearchProgress) is called after every local run (an exception it raises ends the
search and is raised again); a global search takes no callback. InputError naming the field
for a bad search name, max_starts < 1, time_budget <= 0 or seed < 0.

Runs without the GIL; Ctrl-C stops a local run after the current iteration, a global search
after the current local run, and raises KeyboardInterrupt.)doc");
}

}  // namespace

py::dict history_dict(const std::vector<IterationRecord>& history) {
  std::vector<std::int32_t> it, active;
  std::vector<double> f, primal, dual, seconds;
  for (const auto& r : history) {
    it.push_back(r.iteration), active.push_back(r.active);
    f.push_back(r.objective), primal.push_back(r.primal), dual.push_back(r.dual), seconds.push_back(r.seconds);
  }
  py::dict d;
  d["iteration"] = copy(it);
  d["reduced_objective"] = copy(f);
  d["primal"] = copy(primal);
  d["dual"] = copy(dual);
  d["active"] = copy(active);
  d["seconds"] = copy(seconds);
  return d;
}

py::list critical_points_list(const std::shared_ptr<const void>& owner, const MinimizerResult& result,
                              std::optional<double> shift) {
  py::list out;
  for (const CriticalPoint& p : result.critical_points)
    out.append(PyCriticalPoint{std::shared_ptr<const CriticalPoint>(owner, &p), shift});
  return out;
}

bool is_global_search(const std::string& search, const std::string& where) {
  static const std::vector<std::string> names{"local", "global"};
  if (search == "global") return true;
  if (search == "local") return false;
  throw InputError("unknown search '" + search + "'" + did_you_mean(search, names) + " (expected one of: local, global)",
                   where);
}

std::function<void(const GlobalSearchProgress&)> search_progress(SignalWatch& watch, const py::object& progress) {
  // references only: the function is copied with the GIL released
  return [&watch, &progress](const GlobalSearchProgress& g) {
    if (watch.poll()) throw Interrupted{};
    if (progress.is_none()) return;
    {
      py::gil_scoped_acquire gil;
      try {
        progress(g);
      } catch (py::error_already_set& e) {
        e.restore();
        watch.keep_current_error();
      }
    }
    if (watch.interrupted()) throw Interrupted{};
  };
}

const ReducedProblem& ReducedHolder::problem() const { return condensation ? condensation->reduced() : own; }

void register_laws(py::module_& m) {
  py::class_<PyLaw>(m, "ContactLaw", R"doc(
A contact law: the potential j with its DC split j = j1 - j2 (both convex). Shipped laws by
name: hemivem.contact_law("paper"); the law of a reduced problem: reduced.law.
Values and derivatives take a number or an array.
)doc")
      .def_property_readonly("name", [](const PyLaw& l) { return l.law->name(); })
      .def_property_readonly("breakpoints", [](const PyLaw& l) { return l.law->breakpoints(); },
                             "Points where a part is not twice differentiable (sorted).")
      .def_property_readonly("kinks", [](const PyLaw& l) { return l.law->kinks(); },
                             "Breakpoints where j' jumps (the certificate snaps onto them).")
      .def_property_readonly("alpha", [](const PyLaw& l) { return l.law->alpha(); },
                             "The largest negative curvature alpha_j (inf at a concave kink).")
      .def_property_readonly("is_convex", [](const PyLaw& l) { return l.law->is_convex(); })
      .def(
          "value", [](const PyLaw& l, py::handle r, const std::string& part) {
            const LawPart p = part_from(part);
            return map_values(r, [&](double x) { return l.law->value(p, x); });
          },
          py::arg("r"), py::arg("part") = "j", "j(r) (or j1, j2 with part='j1', 'j2').")
      .def(
          "derivative", [](const PyLaw& l, py::handle r, int side, const std::string& part) {
            const LawPart p = part_from(part);
            if (side != -1 && side != 1) throw InputError("side must be -1 or +1", "side");
            return map_values(r, [&](double x) { return l.law->derivative(p, x, side); });
          },
          py::arg("r"), py::arg("side") = 1, py::arg("part") = "j", "j'(r+) (side=+1) or j'(r-) (side=-1).")
      .def(
          "clarke", [](const PyLaw& l, py::handle r) {
            return py::make_tuple(map_values(r, [&](double x) { return l.law->clarke(x).lo; }),
                                  map_values(r, [&](double x) { return l.law->clarke(x).hi; }));
          },
          py::arg("r"),
          "The Clarke subdifferential of j at r as (lo, hi): two floats for a number, two arrays of\n"
          "r's shape for an array.")
      .def("__repr__", [](const PyLaw& l) {
        std::ostringstream o;
        o << "ContactLaw(" << py::repr(py::str(l.law->name())).cast<std::string>() << ", alpha=" << l.law->alpha()
          << ", breakpoints=" << py::repr(py::cast(l.law->breakpoints())).cast<std::string>() << ")";
        return o.str();
      });
  m.def("contact_law", [](const std::string& name) { return PyLaw{make_contact_law(name)}; }, py::arg("name"),
        "A shipped contact law by name (contact_laws()); InputError listing them otherwise.");
  m.def("contact_laws", &contact_law_names, "The names of the shipped contact laws.");
}

void register_reduced(py::module_& m) {
  register_certificate(m);
  register_iteration(m);
  register_critical_point(m);
  register_search_progress(m);
  register_minimizer_result(m);
  ReducedClass reduced = register_reduced_problem(m);
  define_reduced_arrays(reduced);
  define_reduced_origin(reduced);
  define_reduced_methods(reduced);
  define_back_substitute(reduced);
  register_condense(m);
  register_minimize(m);
}

}  // namespace hemivem::python
