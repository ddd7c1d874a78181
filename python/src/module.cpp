// hemivem._hemivem: the module's entry point, NumPy helpers, exceptions, engines, scenes.
#include "bindings.hpp"

#include <hemivem/krylov_solver.hpp>
#include <hemivem/app/outputs.hpp>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::python {

// ---- NumPy helpers ----------------------------------------------------------------------------

py::array view(const double* data, py::ssize_t rows, py::ssize_t cols, py::handle owner, bool c_order) {
  const auto d = static_cast<py::ssize_t>(sizeof(double));
  const std::vector<py::ssize_t> strides = c_order ? std::vector<py::ssize_t>{cols * d, d}
                                                   : std::vector<py::ssize_t>{d, rows * d};
  py::array a(py::dtype::of<double>(), {rows, cols}, strides, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::array view(const double* data, py::ssize_t n, py::handle owner) {
  py::array a(py::dtype::of<double>(), {n}, {static_cast<py::ssize_t>(sizeof(double))}, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::array_t<double> copy(const Eigen::VectorXd& v) {
  py::array_t<double> a(v.size());
  std::copy(v.data(), v.data() + v.size(), a.mutable_data());
  return a;
}

Eigen::VectorXd vector_from(const py::handle& values, const std::string& what, bool finite) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  if (!a) throw InputError("expected an array of numbers", what);
  if (a.ndim() != 1)
    throw InputError("expected a 1-D array, got " + std::to_string(a.ndim()) + " dimensions", what);
  Eigen::VectorXd v(a.shape(0));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    v(i) = a.at(i);
    if (finite && !std::isfinite(v(i)))
      throw InputError(what + "[" + std::to_string(i) + "] = " + std::to_string(v(i)) + " is not finite", what);
  }
  return v;
}

std::string toml_string(const std::string& s) { return nlohmann::json(s).dump(); }

Scene scene_argument(py::object scene, const std::string& function) {
  if (py::isinstance<py::str>(scene) || py::isinstance(scene, py::module_::import("os").attr("PathLike")))
    scene = py::module_::import("hemivem").attr("Scene").attr("from_toml")(scene);  // a file or TOML text
  if (!scene.is_none() && !py::isinstance<Scene>(scene))
    throw py::type_error(function + " takes a Scene, a path to a scene file or TOML text, not " +
                         py::str(scene.get_type().attr("__name__")).cast<std::string>());
  return scene.is_none() ? default_scene() : scene.cast<Scene>();
}

std::vector<std::string> python_linear_engines() {
  std::vector<std::string> engines;
  for (const std::string& name : available_factorizations())
    if (normalized_engine_name(name) != "mumps-mpi") engines.push_back(name);
  return engines;
}

void check_linear_engine(const std::string& linear, const std::string& where) {
  const std::string name = normalized_engine_name(linear);
  if (name == "mumps-mpi")
    throw InputError("'mumps-mpi' runs across processes started by mpirun (hemivem solve --linear mumps-mpi), not "
                     "inside Python; use 'mumps' or another engine of hemivem.available_engines()['linear']",
                     where);
  const std::vector<std::string> engines = python_linear_engines();
  if (name == "auto" || std::find(engines.begin(), engines.end(), name) != engines.end()) return;
  const std::vector<std::string> krylov = available_krylov_solvers();
  if (std::find(krylov.begin(), krylov.end(), name) != krylov.end()) return;
  const std::string available = "; available: " + (engines.empty() ? std::string("none") : join_engine_names(engines));
  throw InputError(is_known_engine(known_linear_engines(), name)
                       ? "linear engine '" + linear + "' was not built" + available
                       : "unknown linear engine '" + linear + "'" + available,
                   where);
}

void refuse_global_keywords(const std::vector<std::pair<std::string, bool>>& given, const std::string& search) {
  std::string names;
  for (const auto& [name, is_given] : given)
    if (is_given) names += (names.empty() ? "" : ", ") + name;
  if (names.empty()) return;
  throw InputError("applies to a global search only, and the search is " + search +
                       "; give search='global', or leave these out",
                   names);
}

// ---- Ctrl-C -------------------------------------------------------------------------------------

SignalWatch::~SignalWatch() {
  if (!type_) return;
  py::gil_scoped_acquire gil;
  Py_XDECREF(type_);
  Py_XDECREF(value_);
  Py_XDECREF(traceback_);
}

bool SignalWatch::poll() {
  py::gil_scoped_acquire gil;
  if (type_) return true;
  if (PyErr_CheckSignals() == 0) return false;
  PyErr_Fetch(&type_, &value_, &traceback_);
  return true;
}

void SignalWatch::keep_current_error() {
  if (type_) {
    PyErr_Clear();
    return;
  }
  PyErr_Fetch(&type_, &value_, &traceback_);
}

void SignalWatch::raise_if_interrupted() {
  if (!type_) return;
  PyErr_Restore(type_, value_, traceback_);
  type_ = value_ = traceback_ = nullptr;
  throw py::error_already_set();
}

// ---- exceptions ----------------------------------------------------------------------------------

namespace {

PyObject* error_type = nullptr;
PyObject* input_error_type = nullptr;
PyObject* mesh_error_type = nullptr;
PyObject* numerical_error_type = nullptr;
PyObject* internal_error_type = nullptr;

PyObject* new_exception(py::module_& m, const char* name, const char* doc, py::tuple bases) {
  const std::string qualified = std::string("hemivem.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, py::handle(type));  // the module keeps a reference; so does the static
  Py_INCREF(type);
  return type;
}

/// Sets the Python error `type(message)` with the attributes where, detail (and element).
void raise(PyObject* type, const std::string& message, const std::string* where = nullptr,
           const std::string* detail = nullptr, const int* element = nullptr) {
  py::object instance = py::reinterpret_borrow<py::object>(type)(message);
  instance.attr("where") = where ? py::str(*where) : py::str("");
  instance.attr("detail") = detail ? py::str(*detail) : py::str(message);
  if (element) instance.attr("element") = *element;
  PyErr_SetObject(type, instance.ptr());
}

}  // namespace

void register_errors(py::module_& m) {
  error_type = new_exception(m, "Error", "Base of every error hemivem raises.", py::make_tuple(py::handle(PyExc_RuntimeError)));
  input_error_type = new_exception(
      m, "InputError",
      "Bad input: a scene key, a file, an engine name, an array entry. A ValueError.\n\n"
      "str(e) is 'where: detail'; e.where names the file and line ('scene.toml:12'), the key\n"
      "('--set contact.gap') or the argument; e.detail is the message alone.",
      py::make_tuple(py::handle(error_type), py::handle(PyExc_ValueError)));
  mesh_error_type = new_exception(m, "MeshError",
                                  "A mesh that breaks a rule of a valid polygonal mesh; e.element is the element "
                                  "(-1 when the defect is not tied to one).",
                                  py::make_tuple(py::handle(input_error_type)));
  numerical_error_type = new_exception(
      m, "NumericalError", "A numerical failure inside an engine (e.g. a stiffness that is not positive definite).",
      py::make_tuple(py::handle(error_type), py::handle(PyExc_ArithmeticError)));
  internal_error_type = new_exception(m, "InternalError", "A broken contract inside hemivem (a programming error).",
                                      py::make_tuple(py::handle(error_type)));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const MeshError& e) {
      const int element = e.element();
      raise(mesh_error_type, e.what(), &e.where(), &e.detail(), &element);
    } catch (const InputError& e) {
      raise(input_error_type, e.what(), &e.where(), &e.detail());
    } catch (const NumericalError& e) {
      raise(numerical_error_type, e.what());
    } catch (const InternalError& e) {
      raise(internal_error_type, e.what());
    } catch (const Error& e) {
      raise(error_type, e.what());
    }
  });
}

// ---- scenes ----------------------------------------------------------------------------------------

void register_scene(py::module_& m) {
  py::class_<Scene>(m, "Scene", R"doc(
A contact problem as data: mesh, material, boundary conditions, contact, solver and outputs
(every key of docs/reference/scenes.md). A Scene is a value: copies are independent.

    scene = hemivem.Scene.default()                 # Example 4.1 on 64 x 64 squares
    scene = hemivem.Scene.from_toml("scenes/hertz.toml")
    scene.set("contact.gap", 0.01)                  # as `hemivem solve --set contact.gap=0.01`
    print(scene.to_toml())
)doc")
      .def(py::init([]() { return default_scene(); }), "Example 4.1 (the default scene).")
      .def_static("default", &default_scene, "Example 4.1 of the paper on 64 x 64 squares (scenes/paper-example-4.1.toml).")
      .def_static(
          "from_file", [](const std::filesystem::path& path) { return parse_scene(path); }, py::arg("path"),
          "Reads and validates a scene file; relative mesh paths are resolved against its folder.\n"
          "InputError naming file:line and the key for every defect.")
      .def_static(
          "from_string",
          [](const std::string& text, const std::string& name) { return parse_scene_string(text, name); },
          py::arg("text"), py::arg("name") = "<string>",
          "Reads a scene from TOML text; `name` stands for the file in messages (and its folder\n"
          "resolves relative mesh paths).")
      .def("_apply_overrides", [](Scene& s, const std::vector<std::string>& kv) { apply_overrides(s, kv); })
      .def("to_toml", [](const Scene& s) { return to_toml(s); },
           "The scene as TOML text, every key written: Scene.from_string(s.to_toml()) == s.")
      .def("write", [](const Scene& s, const std::filesystem::path& path) { write_scene(path, s); }, py::arg("path"),
           "Writes to_toml() to `path` (atomically).")
      .def("copy", [](const Scene& s) { return Scene(s); }, "An independent copy.")
      .def("__copy__", [](const Scene& s) { return Scene(s); })
      .def("__deepcopy__", [](const Scene& s, py::object) { return Scene(s); }, py::arg("memo"))
      .def("__eq__", [](const Scene& a, const Scene& b) { return a == b; }, py::is_operator())
      .def_property_readonly("title", [](const Scene& s) { return s.title; }, "The scene's title.")
      .def_property_readonly("source", [](const Scene& s) { return s.source; },
                             "Where the scene came from: a path, '<default>', '<string>', '<dict>'.")
      .def_property_readonly("mesh_description", [](const Scene& s) { return scene_mesh_description(s); },
                             "How the mesh is made: 'squares n=64', 'voronoi n=[32, 8]', or the file.")
      .def_property_readonly("dimension", [](const Scene& s) { return s.dimension(); },
                             "2, or 3 for a three-dimensional scene (a box domain, a 3D generator or a Gmsh file\n"
                             "of volumes: docs/reference/scenes.md, \"Three-dimensional scenes\").")
      .def_property_readonly("has_contact", [](const Scene& s) { return s.contact.has_value(); },
                             "True when the scene has a contact boundary.")
      .def("where", &Scene::where, py::arg("key"), "'source:line' of a key read from the source, else the source.")
      .def("warnings", [](const Scene& s) { return scene_warnings(s); },
           "What a user should know about the problem (valid, but e.g. driven by nothing).")
      .def("__repr__", [](const Scene& s) {
        std::ostringstream o;
        o << "Scene(" << py::repr(py::str(s.title)).cast<std::string>() << ", source="
          << py::repr(py::str(s.source)).cast<std::string>() << ", mesh="
          << py::repr(py::str(scene_mesh_description(s))).cast<std::string>() << ", contact=" << (s.contact ? "True" : "False")
          << ")";
        return o.str();
      });
}

// ---- engines --------------------------------------------------------------------------------------

void register_engines(py::module_& m) {
  m.def(
      "available_engines",
      []() {
        const std::vector<std::string> linear = python_linear_engines();
        std::vector<std::string> command_only;
        for (const std::string& name : available_factorizations())
          if (std::find(linear.begin(), linear.end(), name) == linear.end()) command_only.push_back(name);
        py::dict d;
        d["linear"] = linear;
        d["krylov"] = available_krylov_solvers();
        d["minimizer"] = available_minimizers();
        d["fastest_linear"] = fastest_factorization();
        d["command_only"] = command_only;
        return d;
      },
      "The engines this module runs: {'linear': [...], 'krylov': [...], 'minimizer': [...],\n"
      "'fastest_linear': name, 'command_only': [...]}. 'auto' (the default linear engine) is\n"
      "'fastest_linear'. A 'krylov' engine given as `linear` solves on the full-space route (nothing\n"
      "factorized; docs/full-space.md). 'command_only'\n"
      "lists the linear engines built that only the hemivem command runs ('mumps-mpi', across the\n"
      "processes mpirun starts); Python refuses them (InputError).");
}

}  // namespace hemivem::python

PYBIND11_MODULE(_hemivem, m) {
  using namespace hemivem::python;
  m.doc() = "hemivem's C++ library for Python (see the package hemivem).";
  m.attr("__version__") = hemivem::app::version();
  register_errors(m);
  register_engines(m);
  register_scene(m);
  register_mesh(m);
  register_laws(m);
  register_reduced(m);
  register_solve(m);
  register_studies(m);
}
