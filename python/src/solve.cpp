// hemivem.solve and its Result: the command's `hemivem solve` pipeline (drivers' solve_scene,
// or solve_scene_3d for a three-dimensional scene) and its output writers.
#include "reduced.hpp"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>
#include <type_traits>
#include <variant>

#include <hemivem/certificate.hpp>
#include <hemivem/error.hpp>
#include <hemivem/uniqueness.hpp>
#include <hemivem/scene/scene.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/report.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/app/stress.hpp>

namespace hemivem::python {

namespace {

/// One solve: the resolved scene, the run (app::run_scene) and the reduced problem.
struct SolveData {
  Scene scene;
  app::SceneRun run;
  std::shared_ptr<ReducedHolder> reduced;  ///< null unless kept and the scene has contact
  std::string json;                        ///< result.json's text, made once
  int dimension() const noexcept { return run.dimension(); }
  const app::SceneSolve& plane() const { return *run.plane(); }
};

/// f applied to the solve of either dimension (SceneSolve or SceneSolve3D: the members they
/// share, e.g. solution.energy, linear, search); f's results must have one type.
template <class F>
auto visit(const SolveData& d, F&& f) {
  if (d.run.solid()) return f(*d.run.solid());
  return f(d.plane());
}

const std::string& json_text(SolveData& d) {
  if (d.json.empty()) d.json = d.run.result_json().dump(2);
  return d.json;
}

py::object json_dict(SolveData& d) { return py::module_::import("json").attr("loads")(json_text(d)); }

/// A number as TOML text for an override: a float stays a float ("60" -> "60.0").
std::string toml_float(double x) {
  std::ostringstream v;
  v << std::setprecision(17) << x;
  std::string text = v.str();
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  return text;
}

/// The contact table as columns (NumPy arrays), one row per contact node.
struct ContactTable {
  py::dict columns;
  py::ssize_t rows = 0;
  std::map<std::string, std::string> absent;  ///< columns of the other dimension: why this table has none
};

/// The error for a column the table does not have.
std::string missing_column(const ContactTable& t, const std::string& name) {
  const auto it = t.absent.find(name);
  return "ContactTable has no column '" + name + "'" + (it == t.absent.end() ? "" : ": " + it->second);
}

ContactTable contact_table(const ContactSolution& s) {
  const auto n = static_cast<py::ssize_t>(s.contact.size());
  py::array_t<std::int32_t> vertex(n);
  py::array_t<double> x(n), y(n), u_nu(n), law_force(n), reaction(n), pressure(n), gap(n), weight(n), u_tau(n),
      friction_force(n), friction_traction(n), normal({n, py::ssize_t(2)});
  py::list state, friction_state, part;
  auto nr = normal.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const ContactNode& c = s.contact[static_cast<std::size_t>(i)];
    vertex.mutable_data()[i] = c.vertex;
    x.mutable_data()[i] = c.x.x(), y.mutable_data()[i] = c.x.y();
    u_nu.mutable_data()[i] = c.u_nu, law_force.mutable_data()[i] = c.law_force, reaction.mutable_data()[i] = c.reaction;
    pressure.mutable_data()[i] = c.pressure(), gap.mutable_data()[i] = c.gap, weight.mutable_data()[i] = c.weight;
    u_tau.mutable_data()[i] = c.u_tau, friction_force.mutable_data()[i] = c.friction_force;
    friction_traction.mutable_data()[i] = c.friction_force / c.weight;
    nr(i, 0) = c.normal.x(), nr(i, 1) = c.normal.y();
    state.append(to_string(c.state)), friction_state.append(to_string(c.friction_state));
    part.append(app::contact_part_name(s, c));
  }
  const py::object np = py::module_::import("numpy");
  ContactTable t;
  t.rows = n;
  t.columns["vertex"] = vertex;
  t.columns["x"] = x;
  t.columns["y"] = y;
  t.columns["u_nu"] = u_nu;
  t.columns["law_force"] = law_force;
  t.columns["reaction"] = reaction;
  t.columns["pressure"] = pressure;
  t.columns["gap"] = gap;
  t.columns["weight"] = weight;
  t.columns["normal"] = normal;
  t.columns["state"] = np.attr("array")(state, py::arg("dtype") = "U");
  t.columns["u_tau"] = u_tau;
  t.columns["friction_force"] = friction_force;
  t.columns["friction_traction"] = friction_traction;
  t.columns["friction_state"] = np.attr("array")(friction_state, py::arg("dtype") = "U");
  t.columns["part"] = np.attr("array")(part, py::arg("dtype") = "U");
  t.absent["z"] = "the contact nodes of a plane body have x and y only";
  return t;
}

/// The contact table of a 3D solve: contact.csv's columns (vertex, x, y, z, u_nu, law_force,
/// reaction, pressure, state, gap, normal as an (n, 3) array) with weight and part.
ContactTable contact_table(const ContactSolution3D& s) {
  const auto n = static_cast<py::ssize_t>(s.contact.size());
  py::array_t<std::int32_t> vertex(n);
  py::array_t<double> x(n), y(n), z(n), u_nu(n), law_force(n), reaction(n), pressure(n), gap(n), weight(n),
      normal({n, py::ssize_t(3)}), u_tau({n, py::ssize_t(3)}), friction_force({n, py::ssize_t(3)}),
      friction_traction({n, py::ssize_t(3)});
  py::list state, friction_state, part;
  auto nr = normal.mutable_unchecked<2>();
  auto ut = u_tau.mutable_unchecked<2>();
  auto ff = friction_force.mutable_unchecked<2>();
  auto ft = friction_traction.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const ContactNode3D& c = s.contact[static_cast<std::size_t>(i)];
    vertex.mutable_data()[i] = c.vertex;
    x.mutable_data()[i] = c.x.x(), y.mutable_data()[i] = c.x.y(), z.mutable_data()[i] = c.x.z();
    u_nu.mutable_data()[i] = c.u_nu, law_force.mutable_data()[i] = c.law_force, reaction.mutable_data()[i] = c.reaction;
    pressure.mutable_data()[i] = c.pressure(), gap.mutable_data()[i] = c.gap, weight.mutable_data()[i] = c.weight;
    for (int d = 0; d < 3; ++d) {
      nr(i, d) = c.normal(d);
      ut(i, d) = c.u_tangential(d);
      ff(i, d) = c.friction_vector(d);
      ft(i, d) = c.friction_vector(d) / c.weight;
    }
    state.append(to_string(c.state)), friction_state.append(to_string(c.friction_state));
    part.append(app::contact_part_name(s, c));
  }
  const py::object np = py::module_::import("numpy");
  ContactTable t;
  t.rows = n;
  t.columns["vertex"] = vertex;
  t.columns["x"] = x;
  t.columns["y"] = y;
  t.columns["z"] = z;
  t.columns["u_nu"] = u_nu;
  t.columns["law_force"] = law_force;
  t.columns["reaction"] = reaction;
  t.columns["pressure"] = pressure;
  t.columns["gap"] = gap;
  t.columns["weight"] = weight;
  t.columns["normal"] = normal;
  t.columns["state"] = np.attr("array")(state, py::arg("dtype") = "U");
  t.columns["u_tau"] = u_tau;
  t.columns["friction_force"] = friction_force;
  t.columns["friction_traction"] = friction_traction;
  t.columns["friction_state"] = np.attr("array")(friction_state, py::arg("dtype") = "U");
  t.columns["part"] = np.attr("array")(part, py::arg("dtype") = "U");
  return t;
}

SolveData& data(py::handle self) { return *self.cast<std::shared_ptr<SolveData>>(); }

py::tuple vector_tuple(const Vec2& v) { return py::make_tuple(v.x(), v.y()); }
py::tuple vector_tuple(const Vec3& v) { return py::make_tuple(v.x(), v.y(), v.z()); }

using ResultClass = py::class_<SolveData, std::shared_ptr<SolveData>>;

/// A Result's loading path, plane or solid, and one of its steps; both keep the Result alive.
/// visit(f) calls f with the path (the step) of the Result's dimension.
struct PyPath {
  std::shared_ptr<SolveData> owner;
  template <class F>
  auto visit(F&& f) const {
    if (const auto* p = owner->run.solid_path()) return f(*p);
    return f(*owner->run.path());
  }
  std::size_t size() const {
    return visit([](const auto& path) { return path.steps.size(); });
  }
};
struct PyPathStep {
  std::shared_ptr<SolveData> owner;
  std::size_t index = 0;
  template <class F>
  auto visit(F&& f) const {
    if (const auto* p = owner->run.solid_path()) return f(p->steps[index]);
    return f(owner->run.path()->steps[index]);
  }
};

py::object json_object(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

template <int dim>
py::array_t<double> vector_array(const Eigen::Matrix<double, dim, 1>& v) {
  py::array_t<double> a(dim);
  for (int c = 0; c < dim; ++c) a.mutable_data()[c] = v(c);
  return a;
}

py::array_t<double> copy_array(const Eigen::VectorXd& v) {
  py::array_t<double> a(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) a.mutable_data()[i] = v(i);
  return a;
}


/// The PathStep property `name`: f(step) for the step of the Result's dimension.
template <class F>
void def_step_property(py::class_<PyPathStep>& c, const char* name, F f) {
  c.def_property_readonly(name, [f](const PyPathStep& s) { return s.visit(f); });
}

void register_path_step(py::module_& m) {
  py::class_<PyPathStep> c(m, "PathStep", R"doc(
One step of a loading path (docs/paths.md), as path.json records it, with its arrays:
index (1-based), t, status, converged, message, certificate (dict), energy, iterations,
contact (ContactTable of the step: u_nu, forces, u_tau, friction_state ...), slip (the slip of
the step per contact node), friction_bound (g_i per node), contact_force and applied_load
(arrays of 2, or 3 for a solid), zone (dict: nodes, length, lower, upper), fixed_point (dict,
or None without a friction bound that depends on the normal contact), jump, change,
displacement ((vertices, 2 or 3) array for a frame, else None) and balance (the relative
residual of the balance of forces, for a frame).
)doc");
  def_step_property(c, "index", [](const auto& s) { return s.index; });
  def_step_property(c, "t", [](const auto& s) { return s.t; });
  def_step_property(c, "status", [](const auto& s) { return to_string(s.status); });
  def_step_property(c, "converged", [](const auto& s) { return s.converged(); });
  def_step_property(c, "message", [](const auto& s) { return s.message; });
  def_step_property(c, "certificate", [](const auto& s) { return json_object(app::certificate_json(s.certificate)); });
  def_step_property(c, "energy", [](const auto& s) { return s.energy; });
  def_step_property(c, "iterations", [](const auto& s) { return s.iterations; });
  def_step_property(c, "slip", [](const auto& s) { return copy_array(s.slip); });
  def_step_property(c, "friction_bound", [](const auto& s) { return copy_array(s.friction_bound); });
  def_step_property(c, "contact_force", [](const auto& s) { return vector_array(s.contact_force); });
  def_step_property(c, "applied_load", [](const auto& s) { return vector_array(s.applied); });
  def_step_property(c, "zone", [](const auto& s) { return json_object(app::path_step_json(s)["contact_zone"]); });
  def_step_property(c, "fixed_point", [](const auto& s) -> py::object {
    const nlohmann::json j = app::path_step_json(s);
    return j["fixed_point"].is_null() ? py::none() : json_object(j["fixed_point"]);
  });
  def_step_property(c, "jump", [](const auto& s) { return s.jump; });
  def_step_property(c, "change", [](const auto& s) { return s.change; });
  def_step_property(c, "balance", [](const auto& s) -> py::object {
    return s.forces ? py::object(py::float_(s.forces->residual())) : py::object(py::none());
  });
  c.def_property_readonly("contact", [](const PyPathStep& p) {
    return p.visit([&p](const auto& s) {
      BasicContactSolution<std::decay_t<decltype(s)>::Point::RowsAtCompileTime> view;
      view.contact = s.contact;
      view.contact_parts = PyPath{p.owner}.visit([](const auto& path) { return path.last.contact_parts; });
      return contact_table(view);
    });
  });
  c.def_property_readonly("displacement", [](py::object self) -> py::object {
    const PyPathStep& p = self.cast<const PyPathStep&>();
    return p.visit([&self](const auto& s) -> py::object {
      constexpr int dim = std::decay_t<decltype(s)>::Point::RowsAtCompileTime;
      if (s.u.size() == 0) return py::none();
      return view(s.u.data(), s.u.size() / dim, dim, self);
    });
  });
  c.def("__repr__", [](const PyPathStep& p) {
    return p.visit([](const auto& s) {
      std::ostringstream o;
      o << "PathStep(index=" << s.index << ", t=" << s.t << ", status='" << to_string(s.status)
        << "', zone_nodes=" << s.zone.nodes << ", jump=" << (s.jump ? "True" : "False") << ")";
      return o.str();
    });
  });
}

/// Per step of the path, f(step), as an array.
template <class F>
py::array_t<double> per_step(const PyPath& p, F f) {
  return p.visit([&f](const auto& path) {
    Eigen::VectorXd v(static_cast<Eigen::Index>(path.steps.size()));
    for (std::size_t k = 0; k < path.steps.size(); ++k) v(static_cast<Eigen::Index>(k)) = f(path.steps[k]);
    return copy_array(v);
  });
}

void register_path_class(py::module_& m) {
  py::class_<PyPath>(m, "Path", R"doc(
The steps of a loading path (Result.path), plane or solid: len(path), path[k] (a PathStep;
negative indices count from the end), iteration over the steps; t, energy (arrays per step),
converged (every step), jumps (the indices of the steps that jumped) and json() (path.json as a
dict).
)doc")
      .def("__len__", [](const PyPath& p) { return p.size(); })
      .def("__getitem__",
           [](const PyPath& p, py::ssize_t k) {
             const auto n = static_cast<py::ssize_t>(p.size());
             if (k < 0) k += n;
             if (k < 0 || k >= n) throw py::index_error("path step index out of range");
             return PyPathStep{p.owner, static_cast<std::size_t>(k)};
           })
      .def("__iter__",
           [](const PyPath& p) {
             py::list steps;
             for (std::size_t k = 0; k < p.size(); ++k) steps.append(py::cast(PyPathStep{p.owner, k}));
             return steps.attr("__iter__")();
           })
      .def_property_readonly("t", [](const PyPath& p) { return per_step(p, [](const auto& s) { return s.t; }); })
      .def_property_readonly("energy", [](const PyPath& p) { return per_step(p, [](const auto& s) { return s.energy; }); })
      .def_property_readonly("converged", [](const PyPath& p) { return p.visit([](const auto& path) { return path.converged(); }); })
      .def_property_readonly("jumps",
                             [](const PyPath& p) {
                               return p.visit([](const auto& path) {
                                 std::vector<int> j;
                                 for (const auto& s : path.steps)
                                   if (s.jump) j.push_back(s.index);
                                 return j;
                               });
                             })
      .def("json", [](const PyPath& p) { return p.visit([](const auto& path) { return json_object(app::path_json(path)); }); },
           "path.json as a dict.")
      .def("__repr__", [](const PyPath& p) {
        return p.visit([](const auto& path) {
          return "Path(" + std::to_string(path.steps.size()) + " steps, t = " + std::to_string(path.steps.back().t) + ")";
        });
      });
}

void register_path(py::module_& m) {
  register_path_step(m);
  register_path_class(m);
}

void register_contact_table(py::module_& m) {
  py::class_<ContactTable>(m, "ContactTable", R"doc(
The contact nodes of a solution as columns (NumPy arrays of equal length, one row per node):
vertex (int32), x, y, u_nu, law_force, reaction, pressure, gap, weight (float64), normal
(n, 2), state ('upper', 'lower', 'free', 'bilateral'), part (the name of the node's contact
part), and with friction u_tau, friction_force, friction_traction, friction_state (empty, and
the numbers 0, at the nodes of a frictionless part). Columns are attributes or items:
table.u_nu, table["u_nu"]; table.as_dict() gives them all.

A three-dimensional solve's table has contact.csv's columns: vertex, x, y, z, u_nu, law_force,
reaction, pressure (force per unit area), gap, weight (the node's share of the contact area),
normal (n, 3), state, part, and the friction columns as vectors in the tangent plane: u_tau
(n, 3) the tangential displacement, friction_force (n, 3) the friction force zeta_t (the
foundation pushes the body by -zeta_t), friction_traction (n, 3) that force per unit area, and
friction_state (zeros and '' at the nodes of a frictionless part).
)doc")
      .def("__getattr__", [](const ContactTable& t, const std::string& name) -> py::object {
        if (!t.columns.contains(name)) throw py::attribute_error(missing_column(t, name));
        return t.columns[py::str(name)];
      })
      .def("__getitem__", [](const ContactTable& t, const std::string& name) -> py::object {
        if (!t.columns.contains(name)) throw py::key_error(missing_column(t, name));
        return t.columns[py::str(name)];
      })
      .def("__len__", [](const ContactTable& t) { return t.rows; })
      .def("__dir__", [](const ContactTable& t) {
        py::list names;
        for (const auto& kv : t.columns) names.append(kv.first);
        return names;
      })
      .def_property_readonly("columns", [](const ContactTable& t) {
        py::list names;
        for (const auto& kv : t.columns) names.append(kv.first);
        return names;
      }, "The column names.")
      .def("as_dict", [](const ContactTable& t) { return py::dict(t.columns); }, "The columns by name (a new dict).")
      .def("__repr__", [](const ContactTable& t) { return "ContactTable(" + std::to_string(t.rows) + " nodes)"; });
}

/// Result's cost: the stages, their seconds and the full-space route's counts.
void def_result_cost(ResultClass& c) {
  c.def_property_readonly("stages", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.stages; }); },
                          "The stages that ran, in order.")
      .def_property_readonly("full_space", [](py::handle s) -> py::object { py::object j = json_dict(data(s)); return j["full_space"]; },
                             "The full-space route's counts as in result.json: newton_iterations,\n"
                             "krylov_iterations (summed over the Newton systems) and preconditioner_setups,\n"
                             "summed over a path, and grid_sequence (the coarser grids solved first, each\n"
                             "{n, unknowns, converged, newton_iterations, krylov_iterations,\n"
                             "preconditioner_setups, seconds}); None on the condensed route.")
      .def_property_readonly("timings", [](py::handle s) -> py::object { py::object j = json_dict(data(s)); return j["timings"]; },
                             "Seconds by stage as in result.json: mesh, assembly, condensation, minimize,\n"
                             "back_substitution (or linear_solve), total.");
}

/// Result's outcome: status, certificate, energy, iterations, engines, search.
void def_result_outcome(ResultClass& c) {
  c.def_property_readonly("dimension", [](py::handle s) { return data(s).dimension(); },
                          "2 for a plane scene, 3 for a three-dimensional one (result.json's \"dimension\"): the\n"
                          "columns of displacement, mesh.vertices and contact.normal.")
      .def_property_readonly("writer", [](py::handle s) { return data(s).run.holds_results(); },
                          "True where write() writes: in one process, and on the first of the processes mpirun\n"
                          "starts for a solve across them (linear='petsc-gamg' or 'petsc-hypre'), which every one\n"
                          "holds whole.")
      .def_property_readonly("status", [](py::handle s) { return visit(data(s), [](const auto& v) { return to_string(v.solution.status); }); },
                          "'converged', 'iteration limit', 'evaluation limit', 'stalled', 'stopped by callback', 'failed', "
                          "'unbounded' (no solution: F is unbounded below).")
      .def_property_readonly("converged", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.converged(); }); })
      .def_property_readonly("message", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.message; }); })
      .def_property_readonly("certificate", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.certificate; }); },
                             "The certificate (primal, dual, scales, tolerance); without contact the relative\n"
                             "residual of the linear solve.")
      .def_property_readonly("energy", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.energy; }); },
                             "The potential energy 1/2 u^T A u - b^T u + sum_i w_i j(u_nu,i).")
      .def_property_readonly("objective", [](py::handle s) {
                               return visit(data(s), [](const auto& v) {
                                 const auto& m = v.solution.minimizer;
                                 return m ? m->objective : std::numeric_limits<double>::quiet_NaN();
                               });
                             },
                             "F(a) of the reduced problem (NaN without contact).")
      .def_property_readonly("uniqueness_margin", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.uniqueness_margin; }); },
                             "lambda_min(S - alpha_j W) (inf without contact), exactly 0 within round-off: the\n"
                             "solution is unique when positive; 0 means F is convex but not strongly convex along\n"
                             "some direction (uniqueness not proved).")
      .def_property_readonly("uniqueness_roundoff", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.uniqueness_roundoff; }); },
                             "The round-off bound of uniqueness_margin (0 without contact).")
      .def_property_readonly("uniqueness", [](py::handle s) {
                               return visit(data(s), [](const auto& v) { return uniqueness_verdict(v.solution.uniqueness_margin); });
                             },
                             "'unique', 'zero', 'negative' or 'unknown' (the margin's verdict).")
      .def_property_readonly("may_be_nonunique", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.may_be_nonunique; }); })
      .def_property_readonly(
          "held_by_contact",
          [](py::handle s) {
            const SolveData& d = data(s);
            return visit(d, [](const auto& v) { return v.solution.held_by_contact; });
          },
          "The rigid motions the Dirichlet conditions leave free, in words; the contact alone holds them\n"
          "(in 2D and 3D alike).")
      .def_property_readonly("iterations", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.solution.iterations(); }); })
      .def_property_readonly("linear", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.linear; }); },
                             "The linear engine used.")
      .def_property_readonly("minimizer", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.minimizer; }); },
                             "The minimizer used (the first engine of a global search).")
      .def_property_readonly(
          "search",
          [](py::handle s) -> py::object {
            return py::module_::import("json").attr("loads")(visit(data(s), [](const auto& v) { return v.search.dump(); }));
          },
          "How the minimizer searched, result.json's \"search\": {'kind': 'local'}, or for a global\n"
          "search its engines and budget (kind, engines, max_starts, time_budget, seed,\n"
          "random_starts, agree).")
      .def_property_readonly(
          "critical_points",
          [](py::object s) {
            const auto d = s.cast<std::shared_ptr<SolveData>>();
            return visit(*d, [&](const auto& v) {
              const auto& sol = v.solution;
              if (!sol.minimizer) return py::list();
              return critical_points_list(d, *sol.minimizer, sol.energy - sol.minimizer->objective);
            });
          },
          "A global search's distinct certified critical points (CriticalPoint), lowest energy first\n"
          "(the solution is the first), with their potential energies: result.json's\n"
          "\"critical_points\". Empty for a local search.")
      .def_property_readonly("warnings", [](py::handle s) { return visit(data(s), [](const auto& v) { return v.warnings; }); },
                             "What the user should know (result.json's \"warnings\"): the scene's, and a\n"
                             "condition number so large that round-off may spoil the displacement's digits.");
}

/// Result.bodies: each body's range and displacement (a scene of several bodies).
void def_result_bodies(ResultClass& c) {
  c.def_property_readonly(
      "bodies",
          [](py::object s) {
            const SolveData& d = data(s);
            const auto& u = *visit(d, [](const auto& v) -> const Eigen::VectorXd* { return &v.solution.u; });
            const auto& bodies = *visit(d, [](const auto& v) -> const std::vector<BodyRange>* { return &v.built->bodies; });
            py::dict out;
            for (const BodyRange& b : bodies) {
              py::dict e;
              e["first_vertex"] = b.first_vertex;
              e["vertices"] = b.vertices;
              e["first_cell"] = b.first_cell;
              e["cells"] = b.cells;
              e["displacement"] = view(u.data() + static_cast<Eigen::Index>(d.dimension()) * b.first_vertex, b.vertices,
                                       d.dimension(), s);
              out[py::str(b.name)] = e;
            }
            return out;
          },
          "A scene of several bodies ([[body]]): per body, by name, its vertices and cells in the mesh\n"
          "(first_vertex, vertices, first_cell, cells) and its displacement, a (vertices, dimension)\n"
          "read-only view of `displacement`'s rows. Empty for a scene of one body.");
}

/// Result's fields: displacement, reduced point, contact table, history, mesh, scene.
/// Result's solution: the displacement, the minimizer's point and result, the contact table,
/// the forces and the history.
void def_result_solution(ResultClass& c) {
  c.def_property_readonly(
       "displacement",
       [](py::object s) {
         const SolveData& d = data(s);
         const Eigen::VectorXd& u = *visit(d, [](const auto& v) -> const Eigen::VectorXd* { return &v.solution.u; });
         return view(u.data(), u.size() / d.dimension(), d.dimension(), s);
       },
       "(num_vertices, 2) float64, C order, read-only view: (ux, uy) per vertex; (num_vertices, 3),\n"
       "(ux, uy, uz), for a three-dimensional scene.")
      .def_property_readonly(
          "a",
          [](py::object s) {
            const MinimizerResult* m = visit(data(s), [](const auto& v) -> const MinimizerResult* {
              return v.solution.minimizer ? &*v.solution.minimizer : nullptr;
            });
            return m ? view(m->a.data(), m->a.size(), s) : view(nullptr, 0, s);
          },
          "The point of the reduced problem (the contact unknowns) the minimizer returned.")
      .def_property_readonly(
          "contact",
          [](py::handle s) { return visit(data(s), [](const auto& v) { return contact_table(v.solution); }); },
          "The contact table (ContactTable): one row per contact node.")
      .def_property_readonly(
          "contact_force",
          [](py::handle s) { return visit(data(s), [](const auto& v) { return vector_tuple(v.solution.contact_force()); }); },
          "The resultant (Fx, Fy) of the foundation or obstacle on the body; (Fx, Fy, Fz) in 3D.")
      .def_property_readonly(
          "forces",
          [](py::handle s) {
            return visit(data(s), [](const auto& v) {
              const auto& b = v.solution.forces;
              py::dict reactions;
              for (const auto& r : b.reactions) reactions[py::str(r.name)] = vector_tuple(r.force);
              py::dict d;
              d["applied"] = vector_tuple(b.applied);
              d["reactions"] = reactions;
              d["contact"] = vector_tuple(b.contact);
              d["balance_residual"] = b.residual();
              return d;
            });
          },
          "The balance of forces on the body, as result.json's \"forces\": {'applied': (Fx, Fy) of the "
          "tractions, pressures and body force, 'reactions': {part name: (Fx, Fy)} per Dirichlet part "
          "('clamped', 'dirichlet[i]'), 'contact': (Fx, Fy) the contact resultant, 'balance_residual': "
          "|applied + reactions + contact| / |applied|}; the forces have three components in 3D.")
      .def_property_readonly(
          "history",
          [](py::handle s) {
            return visit(data(s), [](const auto& v) {
              const auto& m = v.solution.minimizer;
              return history_dict(m ? m->history : std::vector<IterationRecord>());
            });
          },
          "The minimizer's iterations (history.csv's columns) as a dict of arrays.")
      .def_property_readonly(
          "minimizer_result",
          [](py::object s) -> py::object {
            auto d = s.cast<std::shared_ptr<SolveData>>();
            const MinimizerResult* m = visit(*d, [](const auto& v) -> const MinimizerResult* {
              return v.solution.minimizer ? &*v.solution.minimizer : nullptr;
            });
            if (!m) return py::none();
            return py::cast(std::shared_ptr<MinimizerResult>(d, const_cast<MinimizerResult*>(m)));
          },
          "The minimizer's full result (MinimizerResult); None without contact (one linear solve).");
}

/// Result's error estimate and indicators.
void def_result_estimate(ResultClass& c) {
  c.def_property_readonly(
          "error_estimate",
          [](py::handle s) -> py::object {
            const ErrorEstimate* e = visit(data(s), [](const auto& v) -> const ErrorEstimate* { return v.estimate ? &*v.estimate : nullptr; });
            if (!e) return py::none();
            return py::module_::import("json").attr("loads")(app::error_estimate_json(*e).dump());
          },
          "The estimate of the discretization error, as result.json's \"error_estimate\": {'energy': the "
          "estimate of ||u - u_h||_E, 'norm': ||u_h||_E, 'relative': their ratio, 'parts': {name: value}} (its time is "
          "timings['estimate']); None when no estimate was made (a displacement that is not finite).")
      .def_property_readonly(
          "indicators",
          [](py::object s) {
            const ErrorEstimate* e = visit(data(s), [](const auto& v) -> const ErrorEstimate* { return v.estimate ? &*v.estimate : nullptr; });
            return e ? view(e->indicators.data(), static_cast<Eigen::Index>(e->indicators.size()), s)
                     : view(nullptr, 0, s);
          },
          "The error indicators eta_E, one per element (cell in 3D) of `mesh` (float64, read-only view; empty "
          "without an estimate): eta^2 is their sum of squares.");
}

/// The projected stress of every cell of a solve (Result.stress): copies, one row per cell.
struct StressTable {
  py::array_t<double> tensor, von_mises, centroids;
  std::vector<std::string> components;
  std::optional<app::StressPeak> peak;
};

template <class MeshType>
StressTable stress_table(const MeshType& mesh, const MaterialTable& materials, const Eigen::VectorXd& u) {
  constexpr int dim = std::is_same_v<MeshType, Mesh3D> ? 3 : 2;
  const auto cells = app::cell_stresses(mesh, materials, u);
  const auto n = static_cast<py::ssize_t>(cells.size());
  StressTable t;
  t.components = dim == 2 ? std::vector<std::string>{"xx", "yy", "zz", "xy"}
                          : std::vector<std::string>{"xx", "yy", "zz", "yz", "xz", "xy"};
  const auto k = static_cast<py::ssize_t>(t.components.size());
  t.tensor = py::array_t<double>({n, k});
  t.von_mises = py::array_t<double>(n);
  t.centroids = py::array_t<double>({n, py::ssize_t(dim)});
  auto tensor = t.tensor.mutable_unchecked<2>();
  auto centroids = t.centroids.mutable_unchecked<2>();
  for (py::ssize_t e = 0; e < n; ++e) {
    const auto& c = cells[static_cast<std::size_t>(e)];
    if constexpr (dim == 2) {
      tensor(e, 0) = c.xx, tensor(e, 1) = c.yy, tensor(e, 2) = c.zz, tensor(e, 3) = c.xy;
    } else {
      const double values[] = {c.xx, c.yy, c.zz, c.yz, c.xz, c.xy};
      for (py::ssize_t j = 0; j < 6; ++j) tensor(e, j) = values[j];
    }
    t.von_mises.mutable_data()[e] = c.von_mises();
    const auto x = mesh.centroid(static_cast<int>(e));
    for (int j = 0; j < dim; ++j) centroids(e, j) = x(j);
  }
  t.peak = app::stress_peak(mesh, cells);
  return t;
}

void register_stress_table(py::module_& m) {
  py::class_<StressTable>(m, "StressTable", R"doc(
The projected stress of every cell of a solve (Result.stress; stress.csv's rows), constant on
each cell: the stress of the projection Pi u_h with the material of the cell's region.

tensor: (num_cells, 4) for a plane solve, columns xx, yy, zz, xy (zz: lambda (eps_xx + eps_yy)
in plane strain, 0 in plane stress); (num_cells, 6) for a solid, columns xx, yy, zz, yz, xz,
xy. components names the columns. von_mises: (num_cells,), sqrt(((xx - yy)^2 + (yy - zz)^2 +
(zz - xx)^2) / 2 + 3 (yz^2 + xz^2 + xy^2)). centroids: (num_cells, 2 or 3), each cell's
centroid. max_von_mises and max_cell: the largest von Mises stress and the first cell that has
it, as the summary and result.json's "stress" report them (None when a value is not finite).
The arrays are float64 copies, made at each access of Result.stress.
)doc")
      .def_readonly("tensor", &StressTable::tensor)
      .def_readonly("von_mises", &StressTable::von_mises)
      .def_readonly("centroids", &StressTable::centroids)
      .def_property_readonly("components", [](const StressTable& t) { return py::tuple(py::cast(t.components)); })
      .def_property_readonly("max_von_mises",
                             [](const StressTable& t) -> py::object {
                               return t.peak ? py::object(py::float_(t.peak->von_mises)) : py::object(py::none());
                             })
      .def_property_readonly("max_cell",
                             [](const StressTable& t) -> py::object {
                               return t.peak ? py::object(py::int_(t.peak->cell)) : py::object(py::none());
                             })
      .def("__len__", [](const StressTable& t) { return t.von_mises.size(); })
      .def("__repr__", [](const StressTable& t) {
        std::ostringstream o;
        o << std::setprecision(6) << "StressTable(" << t.von_mises.size() << " cells, components=(";
        for (std::size_t j = 0; j < t.components.size(); ++j) o << (j ? ", " : "") << "'" << t.components[j] << "'";
        o << ")";
        if (t.peak) o << ", max_von_mises=" << t.peak->von_mises << ", max_cell=" << t.peak->cell;
        o << ")";
        return o.str();
      });
}

/// Result's stresses.
void def_result_stress(ResultClass& c) {
  c.def_property_readonly(
      "stress",
      [](py::handle s) {
        return visit(data(s), [](const auto& v) {
          return stress_table(v.built->mesh, v.built->problem.elasticity.materials, v.solution.u);
        });
      },
      "The projected stress of every cell (element in the plane) of `mesh`, as stress.csv: a StressTable\n"
      "with tensor ((num_cells, 4): xx, yy, zz, xy in the plane; (num_cells, 6): xx, yy, zz, yz, xz, xy in\n"
      "3D), von_mises (num_cells,), centroids (num_cells, 2 or 3), components, max_von_mises and max_cell.");
}

/// Result's sequences: an adaptive solve's record, a loading path's steps.
void def_result_sequences(ResultClass& c) {
  c.def_property_readonly(
          "adapt",
          [](py::handle s) -> py::object {
            const auto& run = data(s).run;
            const nlohmann::json& a = run.solid() ? run.solid()->adapt : run.plane()->adapt;
            if (a.is_null()) return py::none();
            return py::module_::import("json").attr("loads")(a.dump());
          },
          "An adaptive solve's record, as result.json's \"adapt\": the target and budgets, 'stopped' and "
          "'reason', and 'steps', per solve its unknowns, estimate, potential_energy and elapsed seconds; None "
          "for a solve of one mesh.")
      .def_property_readonly(
          "path",
          [](py::object s) -> py::object {
            auto d = s.cast<std::shared_ptr<SolveData>>();
            if (!d->run.path() && !d->run.solid_path()) return py::none();
            return py::cast(PyPath{d});
          },
          "A loading path's steps (hemivem.solve_path, or a scene with [path] or Coulomb friction): a Path, "
          "a sequence of PathStep; None for a static solve. The Result "
          "itself is the last step's.");
}

/// Result's model: the mesh, the scene and the reduced problem.
void def_result_model(ResultClass& c) {
  c.def_property_readonly(
          "mesh",
          [](py::object s) -> py::object {
            auto d = s.cast<std::shared_ptr<SolveData>>();
            if (d->run.solid()) return py::cast(PyMesh3D{std::shared_ptr<const Mesh3D>(d, &d->run.solid()->built->mesh)});
            return py::cast(PyMesh{std::shared_ptr<const Mesh>(d, &d->plane().built->mesh)});
          },
          "The mesh solved on (shares the result's memory): a Mesh, or a Mesh3D for a three-dimensional scene.")
      .def_property_readonly("scene", [](py::handle s) { return Scene(data(s).scene); },
                             "A copy of the resolved scene (every override applied).")
      .def_property_readonly(
          "reduced", [](py::handle s) -> py::object {
            const auto& r = data(s).reduced;
            return r ? py::cast(r) : py::none();
          },
          "The reduced problem the minimizer solved (solve(..., keep_reduced=True), the default; None\n"
          "without contact). It has no factorization: condense() for back_substitute.");
}

/// Result's documents and files: result.json, the files of `hemivem solve --out`, repr.
void def_result_outputs(ResultClass& c) {
  c.def("json", [](py::handle s) { return json_dict(data(s)); },
        "result.json as a dict (the same document `hemivem solve` writes).")
      .def("to_json", [](py::handle s) { return json_text(data(s)); }, "result.json's text.")
      .def("brief_report", [](py::handle s) {
             return data(s).run.brief();
           },
           "One line: status, certificate, iterations, energy and total time.")
      .def(
          "full_report",
          [](py::handle s) {
            return data(s).run.report();
          },
          "Every stage of the solve, as `hemivem solve` prints it between its title and the files it wrote.")
      .def(
          "write",
          [](py::handle s, const std::filesystem::path& folder, std::optional<std::vector<std::string>> files) {
            SolveData& d = data(s);
            app::OutputReport report;
            {  // across processes the first writes, the others return []
              py::gil_scoped_release release;
              report = d.run.write(folder, files ? &*files : nullptr);
            }
            for (const auto& w : report.warnings)  // a figure not drawn (also in result.json's warnings)
              if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
            std::vector<std::filesystem::path> written = report.written;
            return written;
          },
          py::arg("folder"), py::arg("files") = py::none(),
          "Writes the files `hemivem solve --out folder` writes for this scene (result.json,\n"
          "contact.csv, displacement.csv, stress.csv, history.csv, solution.vtu, scene.toml, and the PNGs when\n"
          "gnuplot is installed; for a three-dimensional scene also contact-surface.vtu, and\n"
          "pressure.png), each atomically; `files` picks some of them by name. Returns the\n"
          "paths written; a figure that could not be drawn is a UserWarning (and in result.json's\n"
          "warnings). Across the processes mpirun starts (linear='petsc-gamg' or 'petsc-hypre'), every\n"
          "process calls it and the first one writes; the others return [].")
      .def("__repr__", [](py::handle s) {
        const SolveData& d = data(s);
        std::ostringstream o;
        visit(d, [&](const auto& v) {
          const auto& sol = v.solution;
          o << "Result(status=" << py::repr(py::str(to_string(sol.status))).cast<std::string>();
          if (d.run.solid()) o << ", dimension=3";
          o << ", linear=" << py::repr(py::str(v.linear)).cast<std::string>()
            << ", minimizer=" << py::repr(py::str(v.minimizer)).cast<std::string>() << ", vertices="
            << v.built->mesh.num_vertices() << ", contact_nodes=" << sol.contact.size() << ", energy=" << std::setprecision(10)
            << sol.energy << ")";
          return 0;
        });
        return o.str();
      });
}

void register_result(py::module_& m) {
  ResultClass c(m, "Result", R"doc(
One solve of a scene (hemivem.solve): what `hemivem solve` reports and writes.

    r = hemivem.solve(hemivem.Scene.default())
    r.status, r.converged, r.certificate, r.energy, r.timings
    r.displacement          # (num_vertices, 2) float64, C order, read-only view
    r.contact.u_nu          # the contact table as arrays
    r.write("out/solve")    # the files of `hemivem solve --out out/solve`

A three-dimensional scene gives a Result of dimension 3: displacement (num_vertices, 3),
contact x, y, z and normal (n, 3), forces of three components, mesh a Mesh3D, indicators one
per cell; adapt is None, the contact table has no friction columns.

A Result holds its own copy of the scene, the mesh and the solution: it outlives the Scene it
was solved from, and its arrays keep it alive.
)doc");
  def_result_outcome(c);
  def_result_cost(c);
  def_result_solution(c);
  def_result_bodies(c);
  def_result_estimate(c);
  def_result_stress(c);
  def_result_sequences(c);
  def_result_model(c);
  def_result_outputs(c);
}

/// The keywords of hemivem.solve that override the scene's [solver].
struct SolveKeywords {
  std::optional<std::string> linear, minimizer;
  std::optional<double> tolerance;
  std::optional<int> max_iterations;
  std::optional<std::string> search;
  std::optional<int> max_starts;
  std::optional<double> time_budget;
  std::optional<int> seed;
  std::optional<std::vector<std::string>> engines;
};

/// The keywords as the command's flags and --set, the further ones as the minimizer's
/// parameters: validated together with the scene.
std::vector<std::string> keyword_overrides(const SolveKeywords& k, const py::kwargs& kwargs) {
  std::vector<std::string> overrides;
  if (k.linear) overrides.push_back("solver.linear=" + toml_string(*k.linear));
  if (k.minimizer) overrides.push_back("solver.minimizer=" + toml_string(*k.minimizer));
  if (k.tolerance) {
    check_tolerance(*k.tolerance, "tolerance");
    overrides.push_back("solver.tolerance=" + toml_float(*k.tolerance));
  }
  if (k.max_iterations) overrides.push_back("solver.max_iterations=" + std::to_string(*k.max_iterations));
  if (k.search) overrides.push_back("solver.search=" + toml_string(*k.search));
  if (k.max_starts) overrides.push_back("solver.max_starts=" + std::to_string(*k.max_starts));
  if (k.time_budget) overrides.push_back("solver.time_budget=" + toml_float(*k.time_budget));
  if (k.seed) overrides.push_back("solver.seed=" + std::to_string(*k.seed));
  if (k.engines) {
    std::string list;
    for (const auto& e : *k.engines) list += (list.empty() ? "" : ", ") + toml_string(e);
    overrides.push_back("solver.search_engines=[" + list + "]");
  }
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    if (py::isinstance<py::bool_>(value) || !(py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)))
      throw InputError("engine parameter '" + name + "' must be a number, got " +
                           py::str(value.get_type().attr("__name__")).cast<std::string>(),
                       name);
    overrides.push_back("solver.parameters." + name + "=" + toml_float(value.cast<double>()));
  }
  return overrides;
}

/// Solves the resolved scene of `d` without the GIL (app::run_scene, as `hemivem solve`),
/// honouring Ctrl-C between stages; keeps the reduced problem when asked and the scene has
/// contact.
void solve_data(SolveData& d, const py::object& progress, bool keep_reduced, bool reduced_optional,
                std::optional<std::variant<Mesh, Mesh3D>> mesh) {
  if (!progress.is_none() && !is_global_search(d.scene.solver.search, "solver.search"))
    throw InputError("only a global search (search='global') reports local runs", "progress");
  SignalWatch watch;
  ReducedProblem reduced;
  try {
    py::gil_scoped_release release;
    app::RunOptions o;
    o.on_built = [&](const app::BuiltSummary&) {
      if (watch.poll()) throw Interrupted{};
    };
    o.callback = [&](const IterationRecord&) { return !watch.poll(); };
    o.reduced = keep_reduced ? &reduced : nullptr;
    o.reduced_key = "keep_reduced";
    o.reduced_optional = reduced_optional;
    o.progress = search_progress(watch, progress);
    o.mesh = std::move(mesh);
    d.run = app::run_scene(d.scene, std::move(o));
  } catch (const Interrupted&) {
  }
  watch.raise_if_interrupted();
  if (keep_reduced && d.run.has_contact() && !reduced.laws.empty()) {
    d.reduced = std::make_shared<ReducedHolder>();
    d.reduced->own = std::move(reduced);
    d.reduced->linear = d.run.linear();
  }
}

constexpr const char* kSolveDoc = R"doc(Solves a scene as `hemivem solve` does: mesh -> assembly -> condensation -> minimizer ->
back-substitution, only the stages the scene needs. Returns a Result.

scene: a Scene (default: Scene.default()), not modified; or a path (str or os.PathLike) to a
scene file, or TOML text, read as Scene.from_toml reads it. linear, minimizer, tolerance and
max_iterations override solver.linear, solver.minimizer, solver.tolerance and
solver.max_iterations (as the flags --linear, --minimizer, --tol); further keyword arguments
are the minimizer's parameters (solver.parameters.NAME, e.g. armijo=1e-3), checked as on the
command line. InputError for a bad key, value, engine name or parameter; NumericalError when
an engine fails. A solve that does not converge is a status, not an error.

search="global" (solver.search, as `hemivem solve --global`) looks for the lowest of several
critical points with every built minimizer, the scene's first; max_starts, time_budget,
seed and engines override solver.max_starts, solver.time_budget, solver.seed and
solver.search_engines (the engines besides the scene's minimizer); given when the search is a
local one (neither search="global" nor the scene's solver.search), they are an InputError naming
them, since they would have no effect. The Result's
critical_points and search are result.json's. progress(SearchProgress) is called after every
local run of a global search (an exception it raises ends the solve and is raised again).

Runs without the GIL; Ctrl-C is honoured between stages (after the mesh, at every minimizer
iteration, after every local run of a global search) and raises KeyboardInterrupt.

mesh: a mesh to solve on instead of the scene's: a Mesh for a plane scene (Mesh.generate,
Mesh.read, Mesh(vertices, elements), or a Result's mesh), a Mesh3D for a solid one
(Mesh3D.generate, or a Result's mesh); the scene's mesh keys are then not used; its boundary
parts, loads, contact parts and region boxes are selected on the given mesh, as on the scene's.
A mesh of the other dimension is an InputError.

adapt=True (or a scene with an [adapt] table) refines adaptively as `hemivem solve --adapt`
does: the Result is the last step's, on the final mesh, with `adapt` holding every step's
numbers; a scene without [adapt] takes its defaults. An adaptive solve keeps no reduced problem
(nor does a loading path): keep_reduced=True with either is an InputError. keep_reduced
defaults to True for a static solve.

A three-dimensional scene (docs/reference/scenes.md, "Three-dimensional scenes") is solved as
`hemivem solve` solves it (solve_scene_3d): the Result has dimension 3, displacement of shape
(num_vertices, 3), a contact table with z and an (n, 3) normal, and a Mesh3D; adapt=True and a
[path] are solved as for a plane scene, the adaptive steps refining the solid's cells.)doc";

void register_solve_function(py::module_& m) {
  m.def(
      "solve",
      [](py::object scene_arg, std::optional<std::string> linear, std::optional<std::string> minimizer,
         std::optional<double> tolerance, std::optional<int> max_iterations, std::optional<std::string> search,
         std::optional<int> max_starts, std::optional<double> time_budget, std::optional<int> seed,
         std::optional<std::vector<std::string>> engines, py::object progress,
         std::optional<bool> keep, py::object mesh, bool adapt, const py::kwargs& kwargs) {
        auto d = std::make_shared<SolveData>();
        d->scene = scene_argument(scene_arg, "hemivem.solve");
        const SolveKeywords k{linear, minimizer, tolerance, max_iterations, search, max_starts, time_budget, seed, engines};
        const std::vector<std::string> overrides = keyword_overrides(k, kwargs);
        if (!overrides.empty()) apply_overrides(d->scene, overrides);
        if (!is_global_search(d->scene.solver.search, "solver.search"))
          refuse_global_keywords({{"max_starts", max_starts.has_value()},
                                  {"time_budget", time_budget.has_value()},
                                  {"seed", seed.has_value()},
                                  {"engines", engines.has_value()}},
                                 "the scene's solver.search = '" + d->scene.solver.search + "'");
        if (adapt && !d->scene.adapt) d->scene.adapt = SceneAdapt{};
        const app::RunKind kind = app::run_kind(d->scene);
        if (kind != app::RunKind::static_solve && keep.value_or(false))
          throw InputError("a" + std::string(kind == app::RunKind::path ? " loading path" : "n adaptive solve") +
                               " has no one reduced problem to keep; leave keep_reduced out",
                           "keep_reduced");
        const bool keep_reduced = kind == app::RunKind::static_solve && keep.value_or(true);
        check_linear_engine(d->scene.solver.linear, linear ? "linear" : d->scene.where("solver.linear"));
        std::optional<std::variant<Mesh, Mesh3D>> given;
        if (py::isinstance<PyMesh>(mesh)) given = *mesh.cast<const PyMesh&>().mesh;
        else if (py::isinstance<PyMesh3D>(mesh)) given = *mesh.cast<const PyMesh3D&>().mesh;
        else if (!mesh.is_none())
          throw py::type_error("hemivem.solve: mesh must be a hemivem.Mesh or a hemivem.Mesh3D, not " +
                               py::str(mesh.get_type().attr("__name__")).cast<std::string>());
        solve_data(*d, progress, keep_reduced, !keep.has_value(), std::move(given));
        return d;
      },
      py::arg("scene") = py::none(), py::kw_only(), py::arg("linear") = py::none(), py::arg("minimizer") = py::none(),
      py::arg("tolerance") = py::none(), py::arg("max_iterations") = py::none(), py::arg("search") = py::none(),
      py::arg("max_starts") = py::none(), py::arg("time_budget") = py::none(), py::arg("seed") = py::none(),
      py::arg("engines") = py::none(), py::arg("progress") = py::none(), py::arg("keep_reduced") = py::none(),
      py::arg("mesh") = py::none(), py::arg("adapt") = false, kSolveDoc);
}

}  // namespace

void register_solve(py::module_& m) {
  register_contact_table(m);
  register_stress_table(m);
  register_path(m);
  register_result(m);
  register_solve_function(m);
}

}  // namespace hemivem::python
