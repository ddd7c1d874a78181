// The scene's values as fields of space at a load factor t, written once for plane (dim = 2)
// and solid (dim = 3) problems (private to the scene module): loads, prescribed displacements,
// gaps and obstacles, and the problem's data set to their values at t (set_load_factor).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

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

/// The name the scene gives prescribed part k of a scene of one body ([clamped] first when it
/// has one, then each [[dirichlet]]), after `prefix` (a body's name and a dot in a scene of
/// several bodies; add_body).
inline std::string prescribed_name(const Scene& one, std::size_t k, const std::string& prefix) {
  const std::size_t clamped = one.clamped.empty() ? 0 : 1;
  return prefix + (k < clamped ? std::string("clamped") : "dirichlet[" + std::to_string(k - clamped) + "]");
}

/// set_load_factor, in either dimension: the body force, each traction or pressure, each
/// prescribed displacement ([clamped], listed first, stays zero), each contact part's gap or
/// obstacle at t. A scene of several bodies: its problem holds each body's prescribed parts
/// and tractions after the previous body's, in body order (built_bodies), and each body's are
/// set from its scene of one body (body_scene); the body force is one for all bodies.
template <int dim>
void set_problem_at(const Scene& scene, double t, BasicContactProblem<dim>& problem) {
  if (!std::isfinite(t)) throw InternalError("set_load_factor: the load factor must be finite, got " + fmt(t));
  auto& e = problem.elasticity;
  // the scene of each body with the name its prescribed parts carry in the problem ("" for one body)
  std::vector<Scene> bodies;
  std::vector<std::string> prefixes;
  if (scene.bodies.empty()) prefixes.emplace_back();
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    bodies.push_back(body_scene(scene, b));
    prefixes.push_back(scene.bodies[b].name + ".");
  }
  const auto one = [&](std::size_t b) -> const Scene& { return scene.bodies.empty() ? scene : bodies[b]; };
  const std::vector<SceneContact> parts = contact_parts(scene);
  std::size_t tractions = 0, prescribed = 0;
  for (std::size_t b = 0; b < prefixes.size(); ++b) {
    tractions += one(b).tractions.size();
    prescribed += (one(b).clamped.empty() ? 0 : 1) + one(b).dirichlet.size();
  }
  const auto not_built = [&](const std::string& why) {
    return InternalError("set_load_factor: the problem was not built from this scene (" + why + ")");
  };
  if (e.tractions.size() != tractions || e.dirichlet.size() != prescribed || parts.size() != problem.parts.size())
    throw not_built(std::to_string(e.tractions.size()) + " tractions, " + std::to_string(e.dirichlet.size()) +
                    " prescribed parts, " + std::to_string(problem.parts.size()) + " contact parts; the scene has " +
                    std::to_string(tractions) + ", " + std::to_string(prescribed) + ", " + std::to_string(parts.size()));
  for (std::size_t k = 0, b = 0, first = 0; k < e.dirichlet.size(); ++k) {
    while (k - first >= (one(b).clamped.empty() ? 0 : 1) + one(b).dirichlet.size())
      first += (one(b).clamped.empty() ? 0 : 1) + one(b).dirichlet.size(), ++b;
    const std::string name = prescribed_name(one(b), k - first, prefixes[b]);
    if (e.dirichlet[k].name != name)
      throw not_built("prescribed part " + std::to_string(k) + " is '" + e.dirichlet[k].name + "', the scene's '" + name + "'");
  }
  e.body_force = body_force_at<dim>(one(0), t);
  for (std::size_t b = 0, traction = 0, held = 0; b < prefixes.size(); ++b) {
    const Scene& s = one(b);
    const std::size_t clamped = s.clamped.empty() ? 0 : 1;
    for (std::size_t i = 0; i < s.tractions.size(); ++i) set_traction_at<dim>(e.tractions[traction + i], s, i, t);
    for (std::size_t i = 0; i < s.dirichlet.size(); ++i)
      e.dirichlet[held + clamped + i].value = dirichlet_value_at<dim>(s, i, t);
    traction += s.tractions.size();
    held += clamped + s.dirichlet.size();
  }
  for (std::size_t i = 0; i < parts.size(); ++i) set_contact_data_at<dim>(problem.parts[i], scene, parts[i], i, t);
}

}  // namespace hemivem::detail
