// Shared pieces of the Python module hemivem._hemivem (python/README.md): NumPy views and
// copies, the exception types, Ctrl-C between stages, and the registration functions of
// each part of the module.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::python {

namespace py = pybind11;

/// A read-only NumPy view of `rows` x `cols` doubles at `data` (row-major when `c_order`, else
/// column-major) that keeps `owner` alive: no copy.
py::array view(const double* data, py::ssize_t rows, py::ssize_t cols, py::handle owner, bool c_order = true);
/// A read-only 1-D view of n doubles.
py::array view(const double* data, py::ssize_t n, py::handle owner);
/// A new 1-D array holding a copy of v.
py::array_t<double> copy(const Eigen::VectorXd& v);
template <class T>
py::array_t<T> copy(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

/// A vector from a 1-D array-like of numbers; InputError naming `what` and the index for an
/// entry that is not finite (when `finite`) and for a shape that is not 1-D.
Eigen::VectorXd vector_from(const py::handle& values, const std::string& what, bool finite = true);

/// A TOML basic string holding s (for overrides "key=value"): its JSON form, which TOML reads.
std::string toml_string(const std::string& s);

/// The linear engines built that Python runs: every one but mumps-mpi, which runs across the
/// processes an MPI launcher starts, never inside a Python interpreter (MPI_Init_thread would
/// wait for the other processes forever).
std::vector<std::string> python_linear_engines();

/// InputError (naming `where`) for a linear engine Python does not run: mumps-mpi, or a name
/// that is not one of python_linear_engines(), available_krylov_solvers() nor "auto", listing
/// the first.
void check_linear_engine(const std::string& linear, const std::string& where);

/// InputError naming the keywords of `given` that were given (name, given) when they apply to a
/// global search only and the search is a local one (`search`, as the caller names it).
void refuse_global_keywords(const std::vector<std::pair<std::string, bool>>& given, const std::string& search);

/// The scene argument of a function: a Scene (copied), None (Scene.default()), or a path (str
/// or os.PathLike) to a scene file or TOML text, read as Scene.from_toml reads it; TypeError
/// naming `function` otherwise.
Scene scene_argument(py::object scene, const std::string& function);

/// A mesh shared with whatever owns it (a result, a reduced problem, or itself).
struct PyMesh {
  std::shared_ptr<const Mesh> mesh;
};

/// A polyhedral mesh shared with the result that owns it.
struct PyMesh3D {
  std::shared_ptr<const Mesh3D> mesh;
};

/// Ctrl-C between the stages of a long call that runs with the GIL released: poll() takes
/// the GIL, runs Python's signal handlers and keeps the exception they raise;
/// raise_if_interrupted() (with the GIL held) raises it.
class SignalWatch {
 public:
  SignalWatch() = default;
  SignalWatch(const SignalWatch&) = delete;
  SignalWatch& operator=(const SignalWatch&) = delete;
  ~SignalWatch();
  /// True when a handler raised (KeyboardInterrupt for Ctrl-C); the GIL must be released.
  bool poll();
  /// Keeps the Python error currently set (the GIL held), e.g. one raised by a user's callback.
  void keep_current_error();
  bool interrupted() const noexcept { return type_ != nullptr; }
  /// Raises the kept exception, if any (the GIL held).
  void raise_if_interrupted();

 private:
  PyObject* type_ = nullptr;
  PyObject* value_ = nullptr;
  PyObject* traceback_ = nullptr;
};

/// Thrown (with the GIL released) to leave a pipeline after poll() returned true.
struct Interrupted {};

void register_errors(py::module_& m);
void register_engines(py::module_& m);
void register_scene(py::module_& m);
void register_mesh(py::module_& m);
void register_laws(py::module_& m);
void register_reduced(py::module_& m);
void register_solve(py::module_& m);
void register_studies(py::module_& m);

}  // namespace hemivem::python
