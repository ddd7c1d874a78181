// The scene's values as fields of space at a load factor t, written once for plane (dim = 2)
// and solid (dim = 3) problems (private to the scene module): loads, prescribed displacements,
// gaps and obstacles, and the problem's data set to their values at t (set_load_factor).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <functional>
#include <string>

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/error.hpp>
#include <hemivem/scene/expression.hpp>
#include <hemivem/scene/scene.hpp>

#include "scene_reader.hpp"

namespace hemivem::detail {

template <int dim>
using Point = Eigen::Matrix<double, dim, 1>;

/// "(x, y)" or "(x, y, z)", for messages.
template <int dim>
std::string point_text(const Point<dim>& x) {
  std::string text = "(";
  for (int c = 0; c < dim; ++c) text += (c ? ", " : "") + fmt(x(c));
  return text + ")";
}

/// A scene value as an expression in the coordinates of the dimension (and t).
template <int dim>
ScalarExpression field(const SceneScalar& v) {
  return v.is_expression() ? ScalarExpression::parse(v.expression, dim) : ScalarExpression(v.value);
}

/// " at t = ..." for a value that depends on t, for messages.
inline std::string at_t(const ScalarExpression& e, double t) { return e.uses_t() ? " at t = " + fmt(t) : std::string(); }

inline bool is_zero(const SceneScalar& v) { return !v.is_expression() && v.value == 0.0; }

/// The scalar field of a driving value of the scene (a load, a prescribed displacement, an
/// obstacle's motion) at the load factor t: times t when it does not mention t, as written when
/// it does (scene.hpp). A value that is not finite is an error naming the scene key.
template <int dim>
std::function<double(const Point<dim>&)> driven_scalar(const SceneScalar& v, double t, const Scene& scene,
                                                       const std::string& key) {
  ScalarExpression e = field<dim>(v);
  const double scale = e.uses_t() ? 1.0 : t;
  return [e = std::move(e), t, scale, key, where = scene.where(key)](const Point<dim>& x) {
    const double value = scale * e(x, t);
    if (!std::isfinite(value))
      throw InputError(key + " = '" + e.text() + "' gives a value that is not finite at " + point_text<dim>(x) + at_t(e, t),
                       where);
    return value;
  };
}

/// The vector field of the first dim driving values of the scene at the load factor t
/// (driven_scalar); `keys` name each component.
template <int dim>
std::function<Point<dim>(const Point<dim>&)> driven_vector(const std::array<SceneScalar, 3>& v, double t,
                                                           const Scene& scene, const std::array<std::string, 3>& keys) {
  std::array<std::function<double(const Point<dim>&)>, dim> f;
  for (int c = 0; c < dim; ++c) f[static_cast<std::size_t>(c)] = driven_scalar<dim>(v[c], t, scene, keys[c]);
  return [f](const Point<dim>& x) {
    Point<dim> out;
    for (int c = 0; c < dim; ++c) out(c) = f[static_cast<std::size_t>(c)](x);
    return out;
  };
}

/// The same key for every component.
inline std::array<std::string, 3> same_key(const std::string& key) { return {key, key, key}; }

/// loads.body_force at t; empty when its components are the number 0.
template <int dim>
std::function<Point<dim>(const Point<dim>&)> body_force_at(const Scene& scene, double t) {
  const auto& f = scene.body_force;
  bool zero = true;
  for (int c = 0; c < dim; ++c) zero = zero && is_zero(f[static_cast<std::size_t>(c)]);
  if (zero) return {};
  return driven_vector<dim>(f, t, scene, same_key("loads.body_force"));
}

/// The traction or pressure of [[loads.traction]] i at t (its edges or faces are not touched).
template <int dim, class Load>
void set_traction_at(Load& load, const Scene& scene, std::size_t i, double t) {
  const auto& traction = scene.tractions[i];
  const std::string key = "loads.traction[" + std::to_string(i) + "]";
  load.traction = {};
  load.pressure = {};
  if (traction.pressure) load.pressure = driven_scalar<dim>(*traction.pressure, t, scene, key + ".pressure");
  else load.traction = driven_vector<dim>(traction.value, t, scene, same_key(key + ".value"));
}

/// The prescribed displacement of [[dirichlet]] i at t (a free component reads 0); empty when
/// every component is the number 0.
template <int dim>
std::function<Point<dim>(const Point<dim>&)> dirichlet_value_at(const Scene& scene, std::size_t i, double t) {
  const auto& d = scene.dirichlet[i];
  const std::string key = "dirichlet[" + std::to_string(i) + "]";
  // the keys that gave the components, for messages
  const bool as_value = scene.lines.count(key + ".value") > 0;
  const std::array<std::string, 3> keys{as_value ? key + ".value" : key + ".ux", as_value ? key + ".value" : key + ".uy",
                                        as_value ? key + ".value" : key + ".uz"};
  const std::array<SceneScalar, 3> value{d.ux.value_or(SceneScalar{}), d.uy.value_or(SceneScalar{}),
                                         d.uz.value_or(SceneScalar{})};
  bool zero = true;
  for (int c = 0; c < dim; ++c) zero = zero && is_zero(value[static_cast<std::size_t>(c)]);
  if (zero) return {};
  return driven_vector<dim>(value, t, scene, keys);
}

/// The gap of contact part i (`c`) at t: as written (a gap that does not mention t stays);
/// finite and >= 0 at every point it is evaluated, else an error naming the key.
template <int dim>
std::function<double(const Point<dim>&)> gap_at(const Scene& scene, const SceneContact& c, std::size_t i, double t) {
  const std::string key = contact_key(scene, i) + ".gap";
  return [g = field<dim>(c.gap), t, key, where = scene.where(key)](const Point<dim>& x) {
    const double value = g(x, t);
    if (!(std::isfinite(value) && value >= 0.0))
      throw InputError(key + " = '" + g.text() + "' gives " + fmt(value) + " at " + point_text<dim>(x) + at_t(g, t) +
                           "; a gap must be finite and >= 0",
                       where);
    return value;
  };
}

/// The obstacle of contact part i (`c`) at t: moved by its motion at t.
template <int dim>
auto obstacle_at(const Scene& scene, const SceneContact& c, std::size_t i, double t) {
  const SceneObstacle& o = *c.obstacle;
  auto b = [&] {
    if constexpr (dim == 2) return make_obstacle(o);
    else return make_obstacle3d(o);
  }();
  if (!o.motion) return b;
  const std::string key = contact_key(scene, i) + ".obstacle.motion";
  const Point<dim> m = driven_vector<dim>(*o.motion, t, scene, same_key(key))(Point<dim>::Zero());
  b.point += m;
  b.center += m;
  if constexpr (dim == 2)
    for (Vec2& q : b.points) q += m;
  return b;
}

/// The gap or the obstacle of contact part i at t.
template <int dim>
void set_contact_data_at(BasicContactPart<dim>& part, const Scene& scene, const SceneContact& c, std::size_t i, double t) {
  if (c.obstacle) part.obstacle = obstacle_at<dim>(scene, c, i, t);
  else part.gap = gap_at<dim>(scene, c, i, t);
}

/// set_load_factor, in either dimension: the body force, each traction or pressure, each
/// prescribed displacement ([clamped], listed first, stays zero), each contact part's gap or
/// obstacle at t.
template <int dim>
void set_problem_at(const Scene& scene, double t, BasicContactProblem<dim>& problem) {
  if (!std::isfinite(t)) throw InternalError("set_load_factor: the load factor must be finite, got " + fmt(t));
  auto& e = problem.elasticity;
  const std::size_t clamped = scene.clamped.empty() ? 0 : 1;  // [clamped] comes first
  const std::vector<SceneContact> parts = contact_parts(scene);
  if (e.tractions.size() != scene.tractions.size() || e.dirichlet.size() != clamped + scene.dirichlet.size() ||
      parts.size() != problem.parts.size())
    throw InternalError("set_load_factor: the problem was not built from this scene (" +
                        std::to_string(e.tractions.size()) + " tractions, " + std::to_string(e.dirichlet.size()) +
                        " prescribed parts, " + std::to_string(problem.parts.size()) + " contact parts; the scene has " +
                        std::to_string(scene.tractions.size()) + ", " + std::to_string(clamped + scene.dirichlet.size()) +
                        ", " + std::to_string(parts.size()) + ")");
  e.body_force = body_force_at<dim>(scene, t);
  for (std::size_t i = 0; i < scene.tractions.size(); ++i) set_traction_at<dim>(e.tractions[i], scene, i, t);
  for (std::size_t i = 0; i < scene.dirichlet.size(); ++i) e.dirichlet[clamped + i].value = dirichlet_value_at<dim>(scene, i, t);
  for (std::size_t i = 0; i < parts.size(); ++i) set_contact_data_at<dim>(problem.parts[i], scene, parts[i], i, t);
}

}  // namespace hemivem::detail
