// The scene schema (docs/reference/scenes.md): a parsed TOML document to a validated Scene.
#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <hemivem/certificate.hpp>
#include <hemivem/engine_names.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/scene/mesh_files3d.hpp>

#include "default_scene_text.hpp"
#include "scene_reader.hpp"
#include <hemivem/support/text_lines.hpp>

namespace hemivem {
namespace detail {

namespace {

const std::vector<std::string> kSides{"left", "right", "top", "bottom"};
/// The sides of a box (select_box_side).
const std::vector<std::string> kSides3{"x0", "x1", "y0", "y1", "z0", "z1", "bottom", "top"};

/// The key `key` of `r` is refused in a three-dimensional scene: an error at its line.
[[noreturn]] void refuse_in_3d(TableReader& r, std::string_view key, const std::string& why = "") {
  r.fail(key, r.node(key), "not available for three-dimensional scenes" + (why.empty() ? "" : " (" + why + ")"));
}

const std::vector<std::string> kSelectorKeys{"side", "group", "segments", "tolerance"};
/// A support's selector ([clamped], [[dirichlet]]) may also hold single vertices.
const std::vector<std::string> kSupportKeys{"side", "group", "segments", "tolerance", "point"};

/// `point` of a support: [x, y] ([x, y, z] in 3D) or an array of them.
std::vector<std::array<double, 3>> read_points(TableReader& r, int dim) {
  std::vector<std::array<double, 3>> out;
  const toml::node* n = r.find("point");
  if (!n) return out;
  const std::string shape = dim == 2 ? "[x, y]" : "[x, y, z]";
  const auto* a = n->as_array();
  if (!a) r.fail_type("point", *n, "an array " + shape + " or an array of them");
  const bool several = !a->empty() && (*a)[0].is_array();
  const std::size_t count = several ? a->size() : 1;
  for (std::size_t i = 0; i < count; ++i) {
    const toml::node& one = several ? (*a)[i] : *n;
    const auto v = r.numbers_of("point", one, "an array " + shape + " or an array of them");
    if (v.size() != static_cast<std::size_t>(dim))
      r.fail("point", one,
             (several ? "point " + std::to_string(i) + ": " : std::string()) + "expected " + shape + " (" +
                 std::to_string(dim) + " numbers), got " + std::to_string(v.size()) + " numbers");
    std::array<double, 3> x{0.0, 0.0, 0.0};
    std::copy(v.begin(), v.end(), x.begin());
    out.push_back(x);
  }
  return out;
}

std::vector<std::string> with_selector(std::vector<std::string> keys) {
  keys.insert(keys.end(), kSelectorKeys.begin(), kSelectorKeys.end());
  return keys;
}

void check_name(TableReader& r, std::string_view key, const std::string& value, const std::vector<std::string>& valid,
                const std::string& what) {
  const std::string v = lower(value);
  for (const auto& x : valid)
    if (v == x) return;
  r.fail(key, r.node(key),
         "unknown " + what + " '" + value + "'" + did_you_mean(value, valid) + " (expected one of: " + join(valid) + ")");
}

/// `support`: the table is a support's, which may hold single vertices (`point`).
BoundarySelector read_selector(TableReader& r, bool required, bool support = false) {
  BoundarySelector s;
  s.sides.clear();
  const bool solid = r.scene().dimension() == 3;
  const std::vector<std::string>& sides = solid ? kSides3 : kSides;
  if (auto v = r.strings("side", true)) {
    for (const auto& side : *v) {
      if (std::find(sides.begin(), sides.end(), lower(side)) == sides.end())
        r.fail("side", r.node("side"),
               "unknown side '" + side + "'" + did_you_mean(side, sides) + " (expected one of: " + join(sides) +
                   (solid ? ", the sides of the box of a three-dimensional mesh" : "") + ")");
      s.sides.push_back(lower(side));
    }
  }
  if (solid && r.has("segments"))
    refuse_in_3d(r, "segments", "select boundary faces by side or by group, a physical surface of a Gmsh file");
  if (auto v = r.strings("group", true)) {
    for (const auto& g : *v)
      if (g.empty()) r.fail("group", r.node("group"), "empty group name");
    s.groups = *v;
  }
  if (r.has("segments")) {
    const toml::node* n = r.find("segments");
    const auto* a = n->as_array();
    if (!a) r.fail_type("segments", *n, "an array of [x0, y0, x1, y1] arrays");
    for (std::size_t i = 0; i < a->size(); ++i) {
      const auto v = r.numbers_of("segments", (*a)[i], "an array of [x0, y0, x1, y1] arrays");
      if (v.size() != 4)
        r.fail("segments", (*a)[i],
               "segment " + std::to_string(i) + ": expected 4 numbers [x0, y0, x1, y1], got " + std::to_string(v.size()));
      s.segments.push_back({v[0], v[1], v[2], v[3]});
    }
  }
  if (auto t = r.number("tolerance")) {
    if (!(*t > 0.0)) r.fail("tolerance", r.node("tolerance"), "must be > 0, got " + fmt(*t));
    s.tolerance = *t;
  }
  if (support) s.points = read_points(r, solid ? 3 : 2);
  if (required && s.empty())
    throw InputError(r.path() + (solid ? ": no boundary given; set side or group" : ": no boundary given; set side, group or segments") +
                         (support ? ", or point" : ""),
                     r.at(r.self()));
  return s;
}

const std::map<std::string, std::vector<std::string>>& law_parameter_names() {
  static const std::map<std::string, std::vector<std::string>> m{{"paper", {}},
                                                                  {"zero", {}},
                                                                  {"linear", {"stiffness"}},
                                                                  {"kinked", {"sigma", "stiffness"}},
                                                                  {"sawtooth", {"stiffness", "r1", "residual", "r2"}},
                                                                  {"piecewise", {}}};
  return m;
}


/// The keys of each friction law in [contact.friction] besides `law`.
const std::map<std::string, std::vector<std::string>>& friction_parameter_names() {
  static const std::map<std::string, std::vector<std::string>> m{{"tresca", {"bound"}},
                                                                  {"slip-weakening", {"static", "kinetic", "distance"}},
                                                                  {"piecewise", {"breakpoints", "j", "j1", "j2"}},
                                                                  {"coulomb", {"coefficient"}}};
  return m;
}

std::vector<std::string> law_names() {
  auto v = contact_law_names();
  v.push_back("piecewise");
  return v;
}


/// breakpoints and either j alone or j1 and j2 of a law = "piecewise" (in the table of `r`;
/// none of them otherwise).
void read_pieces(TableReader& r, SceneLaw& law) {
  const bool piecewise = law.name == "piecewise";
  for (const char* k : {"breakpoints", "j", "j1", "j2"})
    if (r.has(k) && !piecewise) r.fail(k, r.node(k), "only used with law = \"piecewise\" (the law is '" + law.name + "')");
  if (!piecewise) return;
  if (!r.has("breakpoints") || !(r.has("j") || (r.has("j1") && r.has("j2"))))
    r.fail("law", r.node("law"), "law = \"piecewise\" needs breakpoints and either j alone or j1 and j2");
  if (r.has("j") && (r.has("j1") || r.has("j2")))
    r.fail("j", r.node("j"), "give either j alone (the convex split is computed) or j1 and j2, not both");
  law.breakpoints = *r.numbers("breakpoints");
  const std::vector<const char*> parts = r.has("j") ? std::vector<const char*>{"j"} : std::vector<const char*>{"j1", "j2"};
  for (const char* k : parts) {
    auto& pieces = std::string(k) == "j" ? law.j : (std::string(k) == "j1" ? law.j1 : law.j2);
    pieces = *r.matrix(k);
    if (pieces.size() != law.breakpoints.size() + 1)
      r.fail(k, r.node(k),
             "expected " + std::to_string(law.breakpoints.size() + 1) + " pieces (one more than the breakpoints), got " +
                 std::to_string(pieces.size()));
  }
}

/// friction.bound given as [[u_nu, h], ...] (law = "tresca"): the bound h(u_nu), checked as
/// FrictionBound checks it.
void read_bound_table(TableReader& r, SceneLaw& law) {
  const toml::node& n = *r.find("bound");
  const toml::array& a = *n.as_array();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto v = r.numbers_of("bound", a[i], "a number or an array of [u_nu, h] points");
    if (v.size() != 2)
      r.fail("bound", a[i],
             "point " + std::to_string(i + 1) + ": expected [u_nu, h], got " + std::to_string(v.size()) + " numbers");
    law.bound_table.push_back({v[0], v[1]});
  }
  try {
    check_friction_bound(FrictionBound{FrictionBound::Kind::normal_displacement, 0.0, law.bound_table});
  } catch (const InputError& e) {
    r.fail("bound", n, e.detail());
  }
}

/// [contact.friction]: the law of the tangential displacement and its parameters.
SceneLaw read_friction(TableReader& r) {
  SceneLaw law;
  law.name = "tresca";
  if (auto name = r.string("law")) {
    check_name(r, "law", *name, friction_law_names(), "friction law");
    law.name = lower(*name);
  }
  const auto& own = friction_parameter_names().at(law.name);
  for (const auto& [name, keys] : friction_parameter_names())
    for (const auto& k : keys)
      if (name != law.name && r.has(k) && std::find(own.begin(), own.end(), k) == own.end())
        r.fail(k, r.node(k),
               "'" + k + "' is a parameter of friction law '" + name + "', not of '" + law.name + "'" +
                   (own.empty() ? "" : " (which has: " + join(own) + ")"));
  read_pieces(r, law);
  if (law.name == "tresca" && r.has("bound") && r.node("bound").is_array()) read_bound_table(r, law);
  for (const auto& k : own)
    if (k != "breakpoints" && k != "j" && k != "j1" && k != "j2" && law.bound_table.empty())
      if (auto v = r.number(k)) law.parameters[k] = *v;
  if (law.name == "coulomb" && r.has("coefficient")) {
    try {
      check_friction_bound(FrictionBound{FrictionBound::Kind::coulomb, law.parameters.at("coefficient"), {}});
    } catch (const InputError& e) {
      r.fail("coefficient", r.node("coefficient"), e.detail());
    }
  }
  try {
    (void)make_friction_law(law);
  } catch (const InputError& e) {
    const std::string at = r.has("law") || law.parameters.empty() ? "law" : law.parameters.begin()->first;
    r.fail(at, r.has(at) ? r.node(at) : static_cast<const toml::node&>(r.self()), e.detail());
  }
  return law;
}

/// [contact.parameters]: the parameters of the law by name; a parameter of another law names
/// that law.
void read_law_parameters(TableReader& r, const toml::table& p, SceneLaw& law) {
  const auto& allowed = law_parameter_names().at(law.name);
  for (const auto& [k, v] : p) {  // a parameter of another law: name the law
    const std::string key(k.str());
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string owners;
    for (const auto& [other, names] : law_parameter_names())
      if (std::find(names.begin(), names.end(), key) != names.end()) owners += (owners.empty() ? "" : ", ") + other;
    if (owners.empty()) continue;  // unknown to every law: the reader below suggests a name
    r.fail("parameters", v, "'" + key + "' is a parameter of law " + owners + ", not of law '" + law.name + "'" +
                                 (allowed.empty() ? " (which has none)" : " (which has: " + join(allowed) + ")"));
  }
  TableReader pr(r.scene(), p, r.key_path("parameters"), allowed);
  for (const auto& name : allowed)
    if (auto v = pr.number(name)) law.parameters[name] = *v;
}

/// The normal law of [contact]: its name, pieces and parameters, checked by making it.
void read_contact_law(TableReader& r, SceneLaw& law) {
  if (auto name = r.string("law")) {
    check_name(r, "law", *name, law_names(), "contact law");
    law.name = lower(*name);
  }
  read_pieces(r, law);
  if (const toml::table* p = r.table("parameters")) read_law_parameters(r, *p, law);
  try {
    (void)make_law(law);
  } catch (const InputError& e) {
    // a shipped law's parameters out of range: blame [contact.parameters]
    const char* at = r.has("j") ? "j" : (law.parameters.empty() ? "law" : "parameters");
    r.fail(at, r.has(at) ? r.node(at) : static_cast<const toml::node&>(r.self()), e.detail());
  }
}

/// An array of `dims` numbers into the first `dims` coordinates of `out` (the others stay 0).
void read_point(TableReader& ob, const char* key, int dims, std::array<double, 3>& out) {
  if (dims == 3) {
    if (auto v = ob.fixed<3>(key, std::string(key) == "point" || std::string(key) == "center" ? "[x, y, z]" : "[nx, ny, nz]"))
      out = *v;
    return;
  }
  if (auto v = ob.fixed<2>(key, std::string(key) == "point" || std::string(key) == "center" ? "[x, y]" : "[nx, ny]"))
    out = {(*v)[0], (*v)[1], 0.0};
}

/// [contact.obstacle]: a plane (point, normal), a circle (center, radius) or a polyline (points);
/// in three dimensions a plane (point, normal), a sphere (center, radius) or a cylinder (center,
/// axis, radius).
SceneObstacle read_obstacle(TableReader& ob) {
  const int dims = ob.scene().dimension();
  SceneObstacle so;
  if (auto shape = ob.string("shape")) so.shape = lower(*shape);
  if (dims == 3) {
    const std::vector<std::string> solid{"plane", "sphere", "cylinder"};
    if (so.shape == "circle" || so.shape == "polyline")
      ob.fail("shape", ob.node("shape"),
              "'" + so.shape + "' is an obstacle of two-dimensional scenes; a three-dimensional scene takes one of: " +
                  join(solid));
    if (std::find(solid.begin(), solid.end(), so.shape) == solid.end())
      check_name(ob, "shape", so.shape, solid, "obstacle shape");
  } else {
    if (so.shape == "sphere" || so.shape == "cylinder")
      ob.fail("shape", ob.node("shape"),
              "'" + so.shape + "' is an obstacle of three-dimensional scenes; a two-dimensional scene takes one of: "
              "plane, circle, polyline");
    try {
      (void)obstacle_shape_from_string(so.shape);
    } catch (const InputError& e) {
      ob.fail("shape", ob.node("shape"), e.detail());
    }
  }
  const std::map<std::string, std::vector<std::string>> keys{{"plane", {"point", "normal"}},
                                                             {"circle", {"center", "radius"}},
                                                             {"polyline", {"points"}},
                                                             {"sphere", {"center", "radius"}},
                                                             {"cylinder", {"center", "axis", "radius"}}};
  const auto it = keys.find(so.shape);
  for (const char* k : {"point", "normal", "center", "axis", "radius", "points"}) {
    const bool used = std::find(it->second.begin(), it->second.end(), k) != it->second.end();
    if (!used && ob.has(k)) ob.fail(k, ob.node(k), "not used by a " + so.shape + " obstacle");
    if (used && !ob.has(k))
      throw InputError(ob.path() + ": a " + so.shape + " obstacle needs '" + k + "'", ob.at(ob.self()));
  }
  read_point(ob, "point", dims, so.point);
  read_point(ob, "normal", dims, so.normal);
  read_point(ob, "center", dims, so.center);
  if (auto v = ob.fixed<3>("axis", "[ax, ay, az]")) so.axis = *v;
  if (auto v = ob.number("radius")) so.radius = *v;
  if (auto v = ob.points("points")) so.points = *v;
  auto check_motion = [&](const auto& m) {
    const toml::array& a = *ob.node("motion").as_array();
    for (std::size_t i = 0; i < m.size(); ++i)
      if (m[i].is_expression() && ScalarExpression::parse(m[i].expression, dims).uses_position())
        ob.fail("motion", a[i],
                "element " + std::to_string(i) + ": the obstacle moves as a whole, its motion is a function of t "
                "alone; '" + m[i].expression + (dims == 3 ? "' mentions x, y or z" : "' mentions x or y"));
  };
  if (dims == 3) {
    if (auto m = ob.scalars<3>("motion", "[mx, my, mz]")) {
      check_motion(*m);
      so.motion = *m;
    }
  } else if (auto m = ob.scalars<2>("motion", "[mx, my]")) {
    check_motion(*m);
    so.motion = std::array<SceneScalar, 3>{(*m)[0], (*m)[1], SceneScalar{}};
  }
  const std::string defect = dims == 3 ? make_obstacle3d(so).defect() : make_obstacle(so).defect();
  if (!defect.empty()) {
    const char* key = so.shape == "plane" ? "normal"
                      : so.shape == "polyline" ? "points"
                      : so.shape == "cylinder" && !(make_obstacle3d(so).axis.norm() > 0.0) ? "axis"
                                                                                         : "radius";
    ob.fail(key, ob.node(key), defect);
  }
  return so;
}

/// contact.constraint: none, one-sided, box or bilateral (which takes no obstacle).
/// "body.name" of a scene of several bodies: the body (which must exist, and be `body` when that
/// is not empty) and the name.
std::pair<std::string, std::string> body_and_name(TableReader& r, std::string_view key, const std::string& value,
                                                  const std::string& body) {
  const auto& bodies = r.scene().bodies;
  std::vector<std::string> names;
  for (const SceneBody& b : bodies) names.push_back(b.name);
  const auto dot = value.find('.');
  const std::string which = dot == std::string::npos ? std::string() : value.substr(0, dot);
  if (dot == std::string::npos || dot + 1 == value.size() || std::find(names.begin(), names.end(), which) == names.end())
    r.fail(key, r.node(key),
           "'" + value + "': in a scene of several bodies a side or group is named after its body, \"body.side\" (the bodies: " +
               join(names) + ")" + (dot == std::string::npos ? "" : did_you_mean(which, names)));
  if (!body.empty() && which != body)
    r.fail(key, r.node(key), "'" + value + "' is on body '" + which + "', and this part's boundary is on body '" + body +
                                 "': a contact part lies on one body");
  return {which, value.substr(dot + 1)};
}

/// The boundary of a contact part in a scene of several bodies: sides and groups named
/// "body.side", "body.group" (all on one body, `body`).
BoundarySelector read_body_selector(TableReader& r, std::string& body) {
  BoundarySelector s;
  s.sides.clear();
  const bool solid = r.scene().dimension() == 3;
  const std::vector<std::string>& sides = solid ? kSides3 : kSides;
  if (r.has("segments"))
    r.fail("segments", r.node("segments"), "a contact part of a scene of several bodies is selected by side or group (\"body.side\")");
  if (auto v = r.strings("side", true))
    for (const auto& x : *v) {
      auto [b, side] = body_and_name(r, "side", x, body);
      body = b;
      if (std::find(sides.begin(), sides.end(), lower(side)) == sides.end())
        r.fail("side", r.node("side"), "unknown side '" + side + "' of body '" + b + "'" + did_you_mean(side, sides) +
                                           " (expected one of: " + join(sides) + ")");
      s.sides.push_back(lower(side));
    }
  if (auto v = r.strings("group", true))
    for (const auto& x : *v) {
      auto [b, group] = body_and_name(r, "group", x, body);
      body = b;
      s.groups.push_back(group);
    }
  if (auto t = r.number("tolerance")) {
    if (!(*t > 0.0)) r.fail("tolerance", r.node("tolerance"), "must be > 0, got " + fmt(*t));
    s.tolerance = *t;
  }
  if (!s.has_facets())
    throw InputError(r.path() + ": no boundary given; set side or group, named after the body (\"body.side\")", r.at(r.self()));
  return s;
}

/// contact.against = "body.side" (or "body.group"): the other body's surface a part meets. Its
/// gap is 0 and its constraint one-sided unless the part says otherwise.
void read_against(TableReader& r, SceneContact& c) {
  auto a = r.string("against");
  if (!a) {
    if (r.has("pairing")) r.fail("pairing", r.node("pairing"), "used only with against (a part meeting another body)");
    return;
  }
  if (r.scene().bodies.empty())
    r.fail("against", r.node("against"), "names another body's surface; a scene of one body has no other ([[body]] tables)");
  if (r.has("obstacle")) r.fail("against", r.node("against"), "a part meets another body or an obstacle, not both");
  auto [b, name] = body_and_name(r, "against", *a, "");
  if (b == c.body) r.fail("against", r.node("against"), "'" + *a + "' is on the part's own body '" + b + "'");
  const bool solid = r.scene().dimension() == 3;
  const std::vector<std::string>& sides = solid ? kSides3 : kSides;
  BoundarySelector s;
  s.sides.clear();
  if (std::find(sides.begin(), sides.end(), lower(name)) != sides.end()) s.sides.push_back(lower(name));
  else s.groups.push_back(name);
  s.tolerance = c.boundary.tolerance;
  c.against = s;
  c.against_body = b;
  if (auto k = r.string("pairing")) {
    if (*k != "vertex" && *k != "projection")
      r.fail("pairing", r.node("pairing"), "unknown pairing '" + *k + "'; expected vertex or projection");
    c.pairing = *k == "vertex" ? BodyPairing::vertex : BodyPairing::projection;
  }
  if (!r.has("gap")) c.gap = SceneScalar{0.0, {}};
  if (!r.has("constraint")) c.constraint = ConstraintKind::one_sided;
}

void read_constraint(TableReader& r, SceneContact& c) {
  auto k = r.string("constraint");
  if (!k) return;
  try {
    c.constraint = constraint_kind_from_string(*k);
  } catch (const InputError&) {
    r.fail("constraint", r.node("constraint"),
           "unknown constraint '" + *k + "'; expected one of: none, one-sided, box, bilateral");
  }
  if (c.constraint == ConstraintKind::bilateral && c.obstacle)
    r.fail("constraint", r.node("constraint"),
           "'bilateral' keeps the normal displacement at 0 (the body slides on the contact boundary); it takes no "
           "[contact.obstacle]");
}

SceneContact read_contact(TableReader& r) {
  SceneContact c;
  if (auto name = r.string("name")) {
    const bool valid = !name->empty() && name->size() <= 64 &&
                       std::all_of(name->begin(), name->end(), [](char ch) {
                         return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.';
                       });
    if (!valid)
      r.fail("name", r.node("name"),
             "a contact part's name is 1 to 64 letters, digits, '-', '_' or '.', got '" + *name + "'");
    c.name = *name;
  }
  if (r.scene().bodies.empty()) {
    c.boundary = read_selector(r, true);
  } else {
    c.boundary = read_body_selector(r, c.body);
  }
  read_contact_law(r, c.law);
  if (auto g = r.scalar("gap")) {
    if (!g->is_expression() && g->value < 0.0) r.fail("gap", r.node("gap"), "must be >= 0, got " + fmt(g->value));
    c.gap = *g;
  }
  if (const toml::table* o = r.table("obstacle")) {
    if (r.has("gap")) r.fail("gap", r.node("gap"), "not used with [contact.obstacle]; give either a gap or an obstacle");
    TableReader ob(r.scene(), *o, r.key_path("obstacle"),
                   {"shape", "point", "normal", "center", "axis", "radius", "points", "motion"});
    c.obstacle = read_obstacle(ob);
    c.constraint = ConstraintKind::one_sided;  // unless the scene says otherwise
  }
  read_constraint(r, c);
  read_against(r, c);
  if (auto o = r.string("law_origin")) {
    if (*o != "body" && *o != "surface")
      r.fail("law_origin", r.node("law_origin"), "unknown law origin '" + *o + "'; expected body or surface");
    if (*o == "surface" && c.constraint == ConstraintKind::bilateral)
      r.fail("law_origin", r.node("law_origin"), "the bilateral constraint uses no normal law; remove law_origin");
    c.law_origin = *o;
  }
  if (const toml::table* f = r.table("friction")) {
    TableReader fr(r.scene(), *f, r.key_path("friction"),
                   {"law", "bound", "static", "kinetic", "distance", "breakpoints", "j", "j1", "j2", "coefficient"});
    c.friction = read_friction(fr);
    const bool coulomb = c.friction->name == "coulomb";
    if (c.constraint == ConstraintKind::bilateral && (coulomb || !c.friction->bound_table.empty()))
      fr.fail(coulomb ? "law" : "bound", fr.node(coulomb ? "law" : "bound"),
              std::string(coulomb ? "Coulomb's bound mu p" : "a bound h(u_nu)") +
                  " depends on the normal contact and needs the normal displacements as unknowns; constraint = "
                  "\"bilateral\" fixes them at 0 (give the friction bound as a number)");
  }
  return c;
}

/// [contact], or the parts of [[contact]] (keyed "contact" when there is one, "contact[i]"
/// when there are several: contact_key), each named once.
void read_contact_parts(Scene& s, TableReader& r) {
  s.contact.reset();
  s.more_contact.clear();
  const toml::node* n = r.find("contact");
  if (!n) return;
  const std::vector<std::string> keys = with_selector({"name", "law", "parameters", "breakpoints", "j", "j1", "j2", "gap",
                                                       "obstacle", "constraint", "law_origin", "friction", "against", "pairing"});
  std::vector<const toml::table*> tables;
  if (const toml::table* t = n->as_table()) {
    tables.push_back(t);
  } else if (const toml::array* a = n->as_array(); a && a->is_array_of_tables()) {
    for (const toml::node& e : *a) tables.push_back(e.as_table());
  } else if (const toml::array* e = n->as_array(); e && e->empty()) {
    r.fail("contact", *n, "an array of contact parts needs at least one ([[contact]] tables)");
  } else {
    r.fail_type("contact", *n, "a table ([contact]) or an array of tables ([[contact]])");
  }
  std::map<std::string, std::size_t> named;  // explicit names, by part
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const std::string key = tables.size() == 1 ? std::string("contact") : "contact[" + std::to_string(i) + "]";
    TableReader c(s, *tables[i], key, keys);
    SceneContact part = read_contact(c);
    if (!part.name.empty() && !named.emplace(part.name, i).second)
      c.fail("name", c.node("name"),
             "contact part " + std::to_string(named.at(part.name)) + " has the name '" + part.name +
                 "' already; each part has a name of its own");
    if (i == 0) s.contact = std::move(part);
    else s.more_contact.push_back(std::move(part));
  }
}

/// The root's schema_version (required, the one this program reads) and title (else the
/// file's stem).
void read_version_and_title(TableReader& r, Scene& s) {
  const auto version = r.integer("schema_version");
  if (!version)
    throw InputError("missing key 'schema_version'; this program reads schema_version = " +
                         std::to_string(scene_schema_version),
                     s.source);
  if (*version != scene_schema_version)
    r.fail("schema_version", r.node("schema_version"),
           "unsupported version " + std::to_string(*version) + "; this program reads version " +
               std::to_string(scene_schema_version));
  if (auto t = r.string("title")) {
    s.title = *t;
  } else {  // never the paper's title for a scene that does not say it is the paper's problem
    const std::string stem = std::filesystem::path(s.source).stem().string();
    s.title = stem.empty() || stem.front() == '<' || stem.front() == '-' ? "untitled scene" : stem;
  }
}

/// mesh.file: a .poly2d or .msh file, relative to `base`; no generator keys beside it.
void read_mesh_file(TableReader& m, SceneMesh& mesh, const std::filesystem::path& base) {
  for (const char* k : {"generator", "n", "seed", "domain", "center", "radii", "angles", "grading", "focus"})
    if (m.has(k)) m.fail(k, m.node(k), "not used with mesh.file; give either a generator or a file");
  const auto f = *m.string("file");
  if (f.empty()) m.fail("file", m.node("file"), "empty path");
  std::filesystem::path p(f);
  if (p.is_relative()) p = base / p;
  p = p.lexically_normal();
  const std::string ext = lower(p.extension().string());
  if (ext != ".poly2d" && ext != ".msh")
    m.fail("file", m.node("file"), "unknown mesh format '" + p.extension().string() + "'; expected .poly2d or .msh");
  mesh.file = p;
}

/// mesh.n: an integer, or [nx, ny] ([nx, ny, nz] in three dimensions).
void read_mesh_cells(TableReader& m, SceneMesh& mesh) {
  const toml::node& node = *m.find("n");
  const bool solid = mesh.dimension == 3;
  const std::string shapes = solid ? "an integer or [nx, ny, nz]" : "an integer or [nx, ny]";
  const long long most = solid ? 1000 : 10000000;  // the 3D generators take at most 1000 cells per axis
  auto count = [&](const toml::node& k, const std::string& element) {
    const auto* i = k.as_integer();
    if (!i) m.fail("n", k, element + "expected " + shapes + ", got " + type_name(k));
    if (i->get() < 1 || i->get() > most)
      m.fail("n", k, element + "must be between 1 and " + std::to_string(most) + (solid ? " in three dimensions" : "") +
                         ", got " + std::to_string(i->get()));
    return static_cast<int>(i->get());
  };
  if (const auto* a = node.as_array()) {
    if (solid && a->size() != 3)
      m.fail("n", node, "expected [nx, ny, nz] (3 integers) for a three-dimensional mesh, got " +
                            std::to_string(a->size()) + " elements");
    if (!solid && a->size() != 2)
      m.fail("n", node, "expected [nx, ny] (2 integers), got " + std::to_string(a->size()) + " elements" +
                            (a->size() == 3 ? " ([nx, ny, nz] meshes a box: mesh.domain = [x0, x1, y0, y1, z0, z1])" : ""));
    mesh.n = count((*a)[0], "nx: ");
    mesh.ny = count((*a)[1], "ny: ");
    if (solid) mesh.nz = count((*a)[2], "nz: ");
  } else {
    mesh.n = count(node, "");
  }
}

/// mesh.domain: a rectangle [x0, x1, y0, y1], or a polygon [[x0, y0], [x1, y1], ...] for the
/// generators that mesh one; in three dimensions a box [x0, x1, y0, y1, z0, z1].
void read_mesh_domain(TableReader& m, SceneMesh& mesh) {
  const toml::array* domain = m.has("domain") ? m.node("domain").as_array() : nullptr;
  if (mesh.dimension == 3) {
    if (domain && !domain->empty() && (*domain)[0].is_array())
      m.fail("domain", m.node("domain"), "a polygon domain is two-dimensional; a three-dimensional mesh takes a box "
                                         "[x0, x1, y0, y1, z0, z1]");
    if (auto d = m.fixed<6>("domain", "[x0, x1, y0, y1, z0, z1]")) {
      if (!((*d)[0] < (*d)[1] && (*d)[2] < (*d)[3] && (*d)[4] < (*d)[5]))
        m.fail("domain", m.node("domain"), "needs x0 < x1, y0 < y1 and z0 < z1");
      mesh.box = *d;
    }
    return;
  }
  if (domain && !domain->empty() && (*domain)[0].is_array()) {
    mesh.polygon = *m.points("domain");
    PolygonDomain poly;
    for (const auto& p : mesh.polygon) poly.corners.emplace_back(p[0], p[1]);
    const std::string defect = polygon_domain_defect(poly);
    if (!defect.empty()) m.fail("domain", m.node("domain"), "the polygon " + defect);
    if (mesh.generator != "voronoi" && mesh.generator != "triangles")
      m.fail("domain", m.node("domain"),
             "a polygon domain needs generator = \"voronoi\" or \"triangles\" (the generator is \"" +
                 mesh.generator + "\")");
    if (mesh.ny)
      m.fail("n", m.node("n"), "a polygon domain takes one n (cells of about sqrt(area)/n), not [nx, ny]");
  } else if (domain && domain->size() != 4) {
    const auto v = m.numbers_of("domain", m.node("domain"), "an array [x0, x1, y0, y1] or a polygon");
    m.fail("domain", m.node("domain"),
           "expected [x0, x1, y0, y1] (a rectangle), [x0, x1, y0, y1, z0, z1] (a box: a three-dimensional scene) or a "
           "polygon [[x0, y0], [x1, y1], ...], got " + std::to_string(v.size()) + " numbers");
  } else if (auto d = m.fixed<4>("domain", "[x0, x1, y0, y1] or a polygon [[x0, y0], [x1, y1], ...]")) {
    if (!((*d)[0] < (*d)[1] && (*d)[2] < (*d)[3])) m.fail("domain", m.node("domain"), "needs x0 < x1 and y0 < y1");
    mesh.domain = *d;
  }
}

/// The generators that mesh boxes only (cubes, tetrahedra): their name makes a scene
/// three-dimensional.
bool solid_only_generator(const std::string& name) {
  const auto& solid = mesh3d_generator_names();
  const auto& plane = mesh_generator_names();
  return std::find(solid.begin(), solid.end(), name) != solid.end() &&
         std::find(plane.begin(), plane.end(), name) == plane.end();
}

/// The dimension of a generated mesh: the domain decides when given (six numbers: a box),
/// else mesh.n = [nx, ny, nz], else a generator that meshes boxes only.
int generated_dimension(TableReader& m) {
  if (m.has("domain")) {
    const toml::array* d = m.node("domain").as_array();
    return d && d->size() == 6 && !(*d)[0].is_array() ? 3 : 2;
  }
  if (m.has("n")) {
    const toml::array* n = m.node("n").as_array();
    if (n && n->size() == 3) return 3;
  }
  if (m.has("generator"))
    if (const auto* g = m.node("generator").as_string(); g && solid_only_generator(lower(g->get()))) return 3;
  return 2;
}

/// mesh.generator, checked against the generators of the mesh's dimension.
void read_mesh_generator(TableReader& m, SceneMesh& mesh) {
  const bool solid = mesh.dimension == 3;
  if (solid) mesh.generator = "cubes";
  auto g = m.string("generator");
  if (!g) return;
  const std::string name = lower(*g);
  if (solid) {
    const auto& valid = mesh3d_generator_names();
    if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
      const auto& plane = mesh_generator_names();
      if (std::find(plane.begin(), plane.end(), name) != plane.end())
        m.fail("generator", m.node("generator"),
               "mesh generator '" + *g + "' meshes two-dimensional domains; a three-dimensional mesh (a box "
               "mesh.domain = [x0, x1, y0, y1, z0, z1] or mesh.n = [nx, ny, nz]) takes one of: " + join(valid));
      check_name(m, "generator", *g, valid, "three-dimensional mesh generator");
    }
  } else if (name == "polar") {  // a ring, disk or sector: make_polar, with keys of its own
    mesh.generator = name;
    return;
  } else {
    if (solid_only_generator(name))
      m.fail("generator", m.node("generator"),
             "mesh generator '" + *g + "' meshes a box; give mesh.domain = [x0, x1, y0, y1, z0, z1] (the domain is a "
             "rectangle of four numbers)");
    check_name(m, "generator", *g, mesh_generator_names(), "mesh generator");
  }
  mesh.generator = name;
}

/// [mesh]: a file, or a generator with its cell count, seed and domain; its dimension (2, or 3
/// for a box, [nx, ny, nz], a generator of boxes or a Gmsh file of volume elements).
/// The keys of generator = "polar": center, radii, angles (degrees), grading and focus, with
/// n = [radial, around]; checked by making its grid.
void read_mesh_polar(TableReader& m, SceneMesh& mesh) {
  const bool polar = mesh.generator == "polar";
  for (const char* k : {"center", "radii", "angles", "grading", "focus"})
    if (!polar && m.has(k)) m.fail(k, m.node(k), "used only with generator = \"polar\"");
  if (!polar) return;
  if (m.has("domain"))
    m.fail("domain", m.node("domain"), "not used with generator = \"polar\": its domain is center, radii and angles");
  if (!m.has("n") || !mesh.ny)
    throw InputError("mesh: generator = \"polar\" needs n = [cells along the radius, cells around]", m.at(m.self()));
  if (auto c = m.fixed<2>("center", "[x, y]")) mesh.center = *c;
  if (auto r = m.fixed<2>("radii", "[r0, r1]")) mesh.radii = *r;
  if (auto a = m.fixed<2>("angles", "[a0, a1] in degrees")) mesh.angles = *a;
  if (auto g = m.number("grading")) {
    if (!(*g >= 1.0 && *g <= 2.0)) m.fail("grading", m.node("grading"), "must lie in [1, 2], got " + fmt(*g));
    mesh.grading = *g;
  }
  if (auto f = m.number("focus")) mesh.focus = *f;
  try {
    polar_grid(mesh.radii, mesh.angles, mesh.n, *mesh.ny, mesh.grading, mesh.focus);
  } catch (const InputError& e) {
    const char* key = e.detail().find("focus") != std::string::npos   ? "focus"
                      : e.detail().find("angles") != std::string::npos ? "angles"
                      : e.detail().find("radii") != std::string::npos  ? "radii"
                                                                       : "n";
    m.fail(key, m.has(key) ? m.node(key) : m.self(), e.detail().substr(std::string("polar: ").size()));
  }
}

void read_mesh(Scene& s, const toml::table& t, const std::filesystem::path& base) {
  TableReader m(s, t, "mesh", {"generator", "file", "n", "seed", "domain", "center", "radii", "angles", "grading", "focus"});
  if (m.has("file")) {
    read_mesh_file(m, s.mesh, base);
    // the file decides the scene's dimension: one that cannot be read is this key's error
    std::error_code ec;
    if (lower(s.mesh.file.extension().string()) == ".msh" && !std::filesystem::is_regular_file(s.mesh.file, ec))
      m.fail("file", m.node("file"),
             s.mesh.file.string() + (std::filesystem::is_directory(s.mesh.file, ec)
                                         ? ": cannot read the mesh file: it is a directory"
                                         : ": cannot open the mesh file (no such file, or not a regular file)"));
    if (lower(s.mesh.file.extension().string()) == ".msh" && gmsh_file_dimension(s.mesh.file) == 3)
      s.mesh.dimension = 3;
    return;
  }
  s.mesh.dimension = generated_dimension(m);
  read_mesh_generator(m, s.mesh);
  if (m.has("n")) read_mesh_cells(m, s.mesh);
  if (auto seed = m.integer("seed")) {
    if (*seed < 0) m.fail("seed", m.node("seed"), "must be >= 0, got " + std::to_string(*seed));
    s.mesh.seed = *seed;
  }
  read_mesh_polar(m, s.mesh);
  if (s.mesh.generator != "polar") read_mesh_domain(m, s.mesh);
}

/// One [[material.region]]: an id not seen before, E and nu, and an optional box.
SceneRegionMaterial read_region(TableReader& g, std::set<int>& seen) {
  SceneRegionMaterial rm;
  const auto id = g.integer("id");
  if (!id) throw InputError(g.path() + ": missing key 'id'", g.at(g.self()));
  if (*id < 0 || *id > 1000000)
    g.fail("id", g.node("id"), "must be between 0 and 1000000, got " + std::to_string(*id));
  if (!seen.insert(static_cast<int>(*id)).second) g.fail("id", g.node("id"), "region " + std::to_string(*id) + " given twice");
  rm.region = static_cast<int>(*id);
  const auto e = g.number("E");
  const auto nu = g.number("nu");
  if (!e || !nu) throw InputError(g.path() + ": needs both E and nu", g.at(g.self()));
  if (!(*e > 0.0)) g.fail("E", g.node("E"), "must be > 0, got " + fmt(*e));
  if (!(*nu > -1.0 && *nu < 0.5)) g.fail("nu", g.node("nu"), "must lie in (-1, 0.5), got " + fmt(*nu));
  rm.young = *e;
  rm.poisson = *nu;
  if (g.scene().dimension() == 3 && g.has("box"))
    refuse_in_3d(g, "box", "the regions of a three-dimensional mesh are the volume physical groups of its Gmsh file");
  if (auto b = g.fixed<4>("box", "[x0, x1, y0, y1]")) {
    if (!((*b)[0] < (*b)[1] && (*b)[2] < (*b)[3])) g.fail("box", g.node("box"), "needs x0 < x1 and y0 < y1");
    rm.box = *b;
  }
  return rm;
}

/// [material]: E, nu, the plane model, the stabilization and the [[material.region]] overrides.
void read_material(Scene& s, const toml::table& t) {
  TableReader m(s, t, "material", {"E", "nu", "model", "stabilization", "region"});
  if (auto e = m.number("E")) {
    if (!(*e > 0.0)) m.fail("E", m.node("E"), "must be > 0, got " + fmt(*e));
    s.material.young = *e;
  }
  if (auto nu = m.number("nu")) {
    if (!(*nu > -1.0 && *nu < 0.5)) m.fail("nu", m.node("nu"), "must lie in (-1, 0.5), got " + fmt(*nu));
    s.material.poisson = *nu;
  }
  if (s.dimension() == 3 && m.has("model"))
    m.fail("model", m.node("model"),
           "a plane model (plane-strain or plane-stress) applies to two-dimensional scenes; a three-dimensional body "
           "has none: remove the key");
  if (auto model = m.string("model")) {
    try {
      s.material.model = plane_model_from_string(*model);
    } catch (const InputError&) {
      m.fail("model", m.node("model"), "unknown plane model '" + *model + "'; expected one of: plane-strain, plane-stress");
    }
  }
  if (auto st = m.string("stabilization")) {
    try {
      s.material.stabilization = stabilization_from_string(*st);
    } catch (const InputError&) {
      m.fail("stabilization", m.node("stabilization"), "unknown stabilization '" + *st + "'; expected one of: 2mu, trace");
    }
  }
  if (const toml::array* regions = m.array_of_tables("region")) {
    std::set<int> seen;
    for (std::size_t i = 0; i < regions->size(); ++i) {
      TableReader g(s, *(*regions)[i].as_table(), "material.region[" + std::to_string(i) + "]", {"id", "E", "nu", "box"});
      s.material.regions.push_back(read_region(g, seen));
    }
  }
}

/// [clamped]: the boundary held at zero displacement.
void read_clamped(Scene& s, const toml::table& t) {
  TableReader c(s, t, "clamped", kSupportKeys);
  s.clamped = read_selector(c, true, true);
}

/// [[dirichlet]]: prescribed displacements, each value = [ux, uy] or ux and/or uy on a boundary
/// (value = [ux, uy, uz] or any of ux, uy, uz in three dimensions).
void read_dirichlet(Scene& s, const toml::array& d) {
  const bool solid = s.dimension() == 3;
  const std::vector<const char*> components = solid ? std::vector<const char*>{"ux", "uy", "uz"}
                                                    : std::vector<const char*>{"ux", "uy"};
  for (std::size_t i = 0; i < d.size(); ++i) {
    TableReader g(s, *d[i].as_table(), "dirichlet[" + std::to_string(i) + "]",
                  with_selector(solid ? std::vector<std::string>{"value", "ux", "uy", "uz", "point"}
                                      : std::vector<std::string>{"value", "ux", "uy", "point"}));
    SceneDirichlet sd;
    sd.boundary = read_selector(g, true, true);
    auto given = [&] {
      for (const char* k : components)
        if (g.has(k))
          g.fail(k, g.node(k),
                 std::string("not used with value = ") + (solid ? "[ux, uy, uz]" : "[ux, uy]") +
                     "; give either value or " + (solid ? "some of ux, uy, uz" : "ux and/or uy"));
    };
    if (solid) {
      if (auto v = g.scalars<3>("value", "[ux, uy, uz]")) {
        given();
        sd.ux = (*v)[0];
        sd.uy = (*v)[1];
        sd.uz = (*v)[2];
      }
    } else if (auto v = g.scalars<2>("value", "[ux, uy]")) {
      given();
      sd.ux = (*v)[0];
      sd.uy = (*v)[1];
    }
    if (auto v = g.scalar("ux")) sd.ux = *v;
    if (auto v = g.scalar("uy")) sd.uy = *v;
    if (solid)
      if (auto v = g.scalar("uz")) sd.uz = *v;
    if (!sd.ux && !sd.uy && !sd.uz)
      throw InputError(g.path() + (solid ? ": no displacement given; set value = [ux, uy, uz], or some of ux, uy, uz (a "
                                           "roller or a symmetry plane: the others stay free)"
                                         : ": no displacement given; set value = [ux, uy], or ux or uy (a roller)"),
                       g.at(g.self()));
    s.dirichlet.push_back(sd);
  }
}

/// One [[loads.traction]]: a traction value = [tx, ty] or a pressure on a boundary.
SceneTraction read_traction(TableReader& g) {
  SceneTraction st;
  st.boundary = read_selector(g, true);
  const bool solid = g.scene().dimension() == 3;
  const std::string shape = solid ? "[tx, ty, tz]" : "[tx, ty]";
  std::optional<std::array<SceneScalar, 3>> v;
  if (solid) {
    v = g.scalars<3>("value", shape);
  } else if (auto v2 = g.scalars<2>("value", shape)) {
    v = std::array<SceneScalar, 3>{(*v2)[0], (*v2)[1], SceneScalar{}};
  }
  st.pressure = g.scalar("pressure");
  if (v && st.pressure)
    g.fail("pressure", g.node("pressure"), "not used with value = " + shape + "; give either value or pressure");
  if (!v && !st.pressure)
    throw InputError(g.path() + ": missing key 'value' (a traction " + shape + ") or 'pressure' (along the inward normal)",
                     g.at(g.self()));
  if (v) st.value = *v;
  return st;
}

/// [loads]: the body force and the [[loads.traction]] entries (none of either without [loads]).
void read_loads(Scene& s, const toml::table* t) {
  s.tractions.clear();
  if (!t) {
    s.body_force = {};
    return;
  }
  TableReader l(s, *t, "loads", {"body_force", "traction"});
  if (s.dimension() == 3) {
    if (auto f = l.scalars<3>("body_force", "[fx, fy, fz]")) s.body_force = *f;
  } else if (auto f = l.scalars<2>("body_force", "[fx, fy]")) {
    s.body_force = {(*f)[0], (*f)[1], SceneScalar{}};
  }
  if (const toml::array* tr = l.array_of_tables("traction")) {
    for (std::size_t i = 0; i < tr->size(); ++i) {
      TableReader g(s, *(*tr)[i].as_table(), "loads.traction[" + std::to_string(i) + "]",
                    with_selector({"value", "pressure"}));
      s.tractions.push_back(read_traction(g));
    }
  }
}

/// solver.search_engines: names checked here against every known minimizer; whether each was
/// built, when the search is made (an error naming this key's line).
void read_search_engines(TableReader& v, SceneSolver& solver) {
  auto x = v.strings("search_engines", false);
  if (!x) return;
  const auto known = known_minimizers();
  const std::vector<std::string> valid(known.begin(), known.end());
  for (const auto& name : *x) {
    const std::string n = normalized_engine_name(name);
    if (std::find(valid.begin(), valid.end(), n) == valid.end())
      v.fail("search_engines", v.node("search_engines"),
             "unknown minimizer '" + name + "'" + did_you_mean(name, valid) + " (expected some of: " + join(valid) + ")");
    solver.search_engines.push_back(n);
  }
}

/// An integer key of `v` in [lo, hi], if given.
std::optional<int> integer_in(TableReader& v, const char* key, long long lo, long long hi) {
  const auto x = v.integer(key);
  if (x && (*x < lo || *x > hi))
    v.fail(key, v.node(key),
           "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + std::to_string(*x));
  return x ? std::optional<int>(static_cast<int>(*x)) : std::nullopt;
}

/// [solver]: the engines, tolerance, iteration limit, global search and the minimizer's options.
void read_solver(Scene& s, const toml::table& t) {
  TableReader v(s, t, "solver",
                {"linear", "minimizer", "tolerance", "max_iterations", "parameters", "search", "max_starts",
                 "time_budget", "seed", "search_engines", "grid_sequence"});
  if (auto x = v.string("linear")) {
    if (x->empty()) v.fail("linear", v.node("linear"), "empty name");
    s.solver.linear = *x;
  }
  if (auto x = v.string("minimizer")) {
    if (x->empty()) v.fail("minimizer", v.node("minimizer"), "empty name");
    s.solver.minimizer = *x;
  }
  if (auto x = v.number("tolerance")) {
    if (const std::string why = tolerance_problem(*x); !why.empty()) v.fail("tolerance", v.node("tolerance"), why);
    s.solver.tolerance = *x;
  }
  constexpr long long int_max = std::numeric_limits<int>::max();
  if (auto x = integer_in(v, "max_iterations", 1, int_max)) s.solver.max_iterations = *x;
  if (auto x = v.string("search")) {
    check_name(v, "search", *x, {"local", "global"}, "search");
    s.solver.search = lower(*x);
  }
  if (auto x = integer_in(v, "max_starts", 1, 1000000)) s.solver.max_starts = *x;
  if (auto x = v.number("time_budget")) {
    if (!(*x > 0.0) || !std::isfinite(*x))
      v.fail("time_budget", v.node("time_budget"), "must be a finite number of seconds > 0, got " + fmt(*x));
    s.solver.time_budget = *x;
  }
  if (auto x = integer_in(v, "seed", 0, int_max)) s.solver.seed = *x;
  read_search_engines(v, s.solver);
  if (const toml::node* g = v.find("grid_sequence")) {
    if (const auto* text = g->as_string()) {
      if (lower(text->get()) != "auto") v.fail("grid_sequence", *g, "expected \"auto\" or a count of coarser grids, got \"" + text->get() + "\"");
      s.solver.grid_sequence = SceneSolver::grid_sequence_auto;
    } else if (g->is_integer()) {
      if (auto x = integer_in(v, "grid_sequence", 0, 30)) s.solver.grid_sequence = *x;
    } else {
      v.fail_type("grid_sequence", *g, "\"auto\" or a count of coarser grids");
    }
  }
  // the minimizer's typed options by name: the names and ranges are the engine's, checked
  // when the engine is made (its errors name the key's line through Scene::where)
  if (const toml::table* p = v.table("parameters")) {
    std::vector<std::string> names;
    for (const auto& [k, node] : *p) names.emplace_back(k.str());
    TableReader pr(s, *p, "solver.parameters", names);
    for (const auto& name : names)
      if (auto x = pr.number(name)) s.solver.parameters[name] = *x;
  }
}

/// [adapt]: the target, the budgets and the marking fraction.
void read_adapt(Scene& s, const toml::table& t) {
  TableReader v(s, t, "adapt", {"target", "max_unknowns", "max_steps", "fraction"});
  SceneAdapt a;
  if (auto x = v.number("target")) {
    if (!(*x > 0.0 && *x < 1.0))
      v.fail("target", v.node("target"), "must be a relative error in (0, 1), got " + fmt(*x));
    a.target = *x;
  }
  if (auto x = integer_in(v, "max_unknowns", 1, std::numeric_limits<int>::max())) a.max_unknowns = *x;
  if (auto x = integer_in(v, "max_steps", 1, 1000)) a.max_steps = *x;
  if (auto x = v.number("fraction")) {
    if (!(*x > 0.0 && *x <= 1.0))
      v.fail("fraction", v.node("fraction"), "must be a fraction in (0, 1], got " + fmt(*x));
    a.fraction = *x;
  }
  s.adapt = a;
}

/// [path]: the load factors (steps, or t one by one) and the frames written.
void read_path(Scene& s, const toml::table& t) {
  TableReader v(s, t, "path", {"steps", "t", "frames"});
  ScenePath p;
  if (v.has("steps") && v.has("t"))
    throw InputError("path: give either steps (t_k = k / steps) or t (the load factors one by one), not both",
                     v.at(v.node("t")));
  if (auto x = integer_in(v, "steps", 1, 1000000)) p.steps = *x;
  if (auto x = v.numbers("t")) {
    const toml::array& a = *v.node("t").as_array();
    if (x->empty()) v.fail("t", v.node("t"), "needs at least one load factor");
    for (std::size_t i = 0; i < x->size(); ++i) {
      if (!((*x)[i] > 0.0))
        v.fail("t", a[i], "element " + std::to_string(i) + ": a load factor must be > 0, got " + fmt((*x)[i]));
      if (i > 0 && !((*x)[i] > (*x)[i - 1]))
        v.fail("t", a[i],
               "element " + std::to_string(i) + ": the load factors must be strictly increasing, got " +
                   fmt((*x)[i - 1]) + " then " + fmt((*x)[i]));
    }
    p.t = *x;
  }
  if (auto x = integer_in(v, "frames", 1, 1000000)) p.frames = *x;
  s.path = p;
}

/// [output]: the files to write, each named once, and the formats of the figures.
void read_output(Scene& s, const toml::table& t) {
  TableReader o(s, t, "output", {"write", "figure_format"});
  if (auto f = o.strings("figure_format", true)) {
    const auto& valid = scene_figure_formats();
    if (f->empty()) o.fail("figure_format", o.node("figure_format"), "needs at least one format (expected any of: " + join(valid) + ")");
    s.figure_formats.clear();
    for (const auto& x : *f) {
      if (std::find(valid.begin(), valid.end(), lower(x)) == valid.end())
        o.fail("figure_format", o.node("figure_format"),
               "unknown figure format '" + x + "'" + did_you_mean(x, valid) + " (expected any of: " + join(valid) + ")");
      if (std::find(s.figure_formats.begin(), s.figure_formats.end(), lower(x)) == s.figure_formats.end())
        s.figure_formats.push_back(lower(x));
    }
  }
  auto w = o.strings("write", false);
  if (!w) return;
  s.outputs.clear();
  for (const auto& x : *w) {
    const auto& valid = scene_output_names();
    if (std::find(valid.begin(), valid.end(), lower(x)) == valid.end())
      o.fail("write", o.node("write"),
             "unknown output '" + x + "'" + did_you_mean(x, valid) + " (expected any of: " + join(valid) + ")");
    if (std::find(s.outputs.begin(), s.outputs.end(), lower(x)) == s.outputs.end()) s.outputs.push_back(lower(x));
  }
}

/// One [[body]] table: its name, mesh (required), material, supports and loads, read as a scene
/// of one body reads them.
SceneBody read_body(Scene& s, const toml::table& t, std::size_t i, const std::filesystem::path& base) {
  Scene one;
  one.source = s.source;
  one.lines.clear();
  const std::string key = "body[" + std::to_string(i) + "]";
  TableReader r(one, t, key, {"name", "mesh", "material", "clamped", "dirichlet", "loads"});
  SceneBody body;
  auto name = r.string("name");
  if (!name) throw InputError(key + ": missing key 'name' (each body is named: name = \"upper\")", r.at(r.self()));
  if (!valid_body_name(*name))
    r.fail("name", r.node("name"), "a body's name is 1 to 64 ASCII letters, digits, '-' or '_', got '" + *name + "'");
  for (const SceneBody& b : s.bodies) {
    if (b.name == *name) r.fail("name", r.node("name"), "two bodies are named '" + *name + "'");
    if (lower(b.name) == lower(*name))
      r.fail("name", r.node("name"), "bodies '" + b.name + "' and '" + *name +
                                         "' differ in case only: they would name one output file where case is ignored");
  }
  body.name = *name;
  const toml::table* mesh = r.table("mesh");
  if (!mesh) throw InputError(key + ": missing table 'mesh' (each body has its own mesh)", r.at(r.self()));
  read_mesh(one, *mesh, base);
  if (const toml::table* m = r.table("material")) read_material(one, *m);
  one.clamped = BoundarySelector{{}, {}, {}, 1e-8, {}};
  if (const toml::table* c = r.table("clamped")) read_clamped(one, *c);
  if (const toml::array* d = r.array_of_tables("dirichlet")) read_dirichlet(one, *d);
  read_loads(one, r.table("loads"));
  body.mesh = one.mesh;
  body.material = one.material;
  body.clamped = one.clamped;
  body.dirichlet = one.dirichlet;
  body.body_force = one.body_force;
  body.tractions = one.tractions;
  body.lines = one.lines;
  for (const auto& [k, line] : one.lines) s.lines[k.rfind(key, 0) == 0 ? k : key + "." + k] = line;
  return body;
}

/// [[body]]: the bodies of a scene of several, all of one dimension; the scene's own mesh,
/// material, supports and loads are then refused.
void read_bodies(Scene& s, TableReader& r, const std::filesystem::path& base) {
  s.bodies.clear();
  const toml::array* a = r.array_of_tables("body");
  if (!a) return;
  if (a->size() < 2) r.fail("body", r.node("body"), "a scene of several bodies has at least two [[body]] tables");
  for (const char* k : {"mesh", "material", "clamped", "dirichlet", "loads"})
    if (r.has(k))
      r.fail(k, r.node(k), "not used in a scene of several bodies: each [[body]] has its own mesh, material, supports and loads");
  for (std::size_t i = 0; i < a->size(); ++i) {
    s.bodies.push_back(read_body(s, *(*a)[i].as_table(), i, base));
    if (s.bodies.back().mesh.dimension != s.bodies.front().mesh.dimension)
      r.fail("body", (*a)[i], "body '" + s.bodies.back().name + "' is of dimension " +
                                  std::to_string(s.bodies.back().mesh.dimension) + " and body '" + s.bodies.front().name +
                                  "' of dimension " + std::to_string(s.bodies.front().mesh.dimension) +
                                  ": the bodies of a scene are all plane or all solid");
  }
  s.mesh.dimension = s.bodies.front().mesh.dimension;
  s.clamped = BoundarySelector{{}, {}, {}, 1e-8, {}};
  s.dirichlet.clear();
  s.tractions.clear();
  s.body_force = {};
}

}  // namespace

Scene scene_from_table(const toml::table& root, std::string source, const std::filesystem::path& base) {
  Scene s;
  s.source = std::move(source);
  s.lines.clear();
  TableReader r(s, root, "",
                {"schema_version", "title", "mesh", "material", "clamped", "dirichlet", "loads", "contact", "solver", "adapt",
                 "path", "output", "body"});
  read_version_and_title(r, s);
  read_bodies(s, r, base);
  if (s.bodies.empty()) {
    if (const toml::table* t = r.table("mesh")) read_mesh(s, *t, base);
    if (const toml::table* t = r.table("material")) read_material(s, *t);
    if (!r.has("clamped")) s.clamped = BoundarySelector{{}, {}, {}, 1e-8, {}};  // only the supports the scene writes
    if (const toml::table* t = r.table("clamped")) read_clamped(s, *t);
    if (const toml::array* d = r.array_of_tables("dirichlet")) read_dirichlet(s, *d);
    read_loads(s, r.table("loads"));
  }
  read_contact_parts(s, r);
  if (const toml::table* t = r.table("solver")) read_solver(s, *t);
  s.adapt.reset();
  if (const toml::table* t = r.table("adapt")) read_adapt(s, *t);
  s.path.reset();
  if (const toml::table* t = r.table("path")) read_path(s, *t);
  if (const toml::table* t = r.table("output")) read_output(s, *t);
  if (!s.bodies.empty() && r.has("adapt"))
    r.fail("adapt", r.node("adapt"),
           "a scene of several bodies is solved on the meshes its bodies make; [adapt] is not available for it");
  return s;
}

}  // namespace detail

using detail::base_folder;
using detail::parse_toml;
using detail::scene_from_table;

const std::vector<std::string>& scene_output_names() {
  static const std::vector<std::string> names{"vtu",         "contact-csv", "displacement-csv", "stress-csv",
                                              "history-csv", "result-json", "u-nu-png",         "deformed-png",
                                              "error-png",   "mesh-png",    "adapt-png",        "pressure-png"};
  return names;
}

const std::vector<std::string>& scene_figure_formats() {
  static const std::vector<std::string> formats{"png", "pdf", "svg"};
  return formats;
}

bool valid_body_name(const std::string& name) {
  return !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char ch) {
           return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '-' || ch == '_';
         });
}

std::string SceneMesh::description() const {
  if (!file.empty()) return file.string();
  return generator + " n=" + n_text();
}

std::vector<double> ScenePath::factors() const {
  if (!t.empty()) return t;
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(std::max(steps, 0)));
  for (int k = 1; k <= steps; ++k) out.push_back(static_cast<double>(k) / steps);
  return out;
}

bool ScenePath::is_frame(int step) const {
  const long long K = t.empty() ? steps : static_cast<long long>(t.size());
  const long long k = step, F = frames;
  if (k < 1 || k > K) return false;
  return k == K || (k * F) / K != ((k - 1) * F) / K;
}

bool operator==(const ScenePath& a, const ScenePath& b) {
  return a.t == b.t && (!a.t.empty() || a.steps == b.steps) && a.frames == b.frames;
}

bool Scene::writes(std::string_view output) const {
  return std::find(outputs.begin(), outputs.end(), output) != outputs.end();
}

std::string Scene::where(const std::string& key) const {
  auto it = lines.find(key);
  if (it == lines.end() || it->second <= 0) return source;
  return source + ":" + std::to_string(it->second);
}

bool operator==(const Scene& a, const Scene& b) {
  return a.schema_version == b.schema_version && a.title == b.title && a.mesh == b.mesh && a.material == b.material &&
         a.clamped == b.clamped && a.dirichlet == b.dirichlet && a.body_force == b.body_force &&
         a.tractions == b.tractions && a.contact == b.contact && a.more_contact == b.more_contact &&
         a.solver == b.solver && a.adapt == b.adapt && a.path == b.path && a.outputs == b.outputs &&
         a.figure_formats == b.figure_formats && a.bodies == b.bodies;
}

Scene body_scene(const Scene& scene, std::size_t b) {
  if (b >= scene.bodies.size())
    throw InputError("body " + std::to_string(b) + " of a scene of " + std::to_string(scene.bodies.size()) + " bodies");
  const SceneBody& body = scene.bodies[b];
  Scene one;
  one.title = scene.title;
  one.source = scene.source;
  one.lines = body.lines;
  one.mesh = body.mesh;
  one.material = body.material;
  one.clamped = body.clamped;
  one.dirichlet = body.dirichlet;
  one.body_force = body.body_force;
  one.tractions = body.tractions;
  one.solver = scene.solver;
  one.outputs = scene.outputs;
  one.figure_formats = scene.figure_formats;
  one.contact.reset();
  for (std::size_t k = 0; k < contact_parts(scene).size(); ++k) {
    SceneContact part = contact_parts(scene)[k];
    if (part.body != body.name) continue;
    if (part.name.empty()) part.name = contact_part_name(scene, k);
    part.body.clear();
    part.against.reset();
    part.against_body.clear();
    if (!one.contact) one.contact = std::move(part);
    else one.more_contact.push_back(std::move(part));
  }
  return one;
}

std::vector<SceneContact> contact_parts(const Scene& scene) {
  std::vector<SceneContact> parts;
  if (!scene.contact) return parts;
  parts.push_back(*scene.contact);
  parts.insert(parts.end(), scene.more_contact.begin(), scene.more_contact.end());
  return parts;
}

bool every_selector(const Scene& scene, const std::function<bool(const BoundarySelector&)>& holds) {
  if (!holds(scene.clamped)) return false;
  for (const SceneDirichlet& d : scene.dirichlet)
    if (!holds(d.boundary)) return false;
  for (const SceneTraction& t : scene.tractions)
    if (!holds(t.boundary)) return false;
  if (scene.contact && !holds(scene.contact->boundary)) return false;
  for (const SceneContact& c : scene.more_contact)
    if (!holds(c.boundary)) return false;
  return true;
}

std::string contact_key(const Scene& scene, std::size_t part) {
  return scene.more_contact.empty() ? std::string("contact") : "contact[" + std::to_string(part) + "]";
}

std::string contact_part_name(const Scene& scene, std::size_t part) {
  const SceneContact* c = part == 0 ? (scene.contact ? &*scene.contact : nullptr)
                                    : (part - 1 < scene.more_contact.size() ? &scene.more_contact[part - 1] : nullptr);
  return c && !c->name.empty() ? c->name : contact_key(scene, part);
}

Scene parse_scene_string(std::string_view text, std::string name) {
  const toml::table root = parse_toml(text, name);
  Scene s = scene_from_table(root, name, base_folder(name));
  s.document = std::make_shared<const detail::SceneDocument>(detail::SceneDocument{std::string(text), base_folder(name), {}, s});
  return s;
}

Scene parse_scene(const std::filesystem::path& path) {
  text::require_regular_file(path, "scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open scene file", path.string());
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError("read error while reading the scene file", path.string());
  return parse_scene_string(ss.str(), path.string());
}

Scene default_scene() { return parse_scene_string(detail::default_scene_text(), "<default>"); }

}  // namespace hemivem
