// A Scene as TOML text: every key written, so that the text reads back as the same scene.
#include <hemivem/scene/scene.hpp>

#include <cstdio>
#include <sstream>

#include <hemivem/support/atomic_file.hpp>

#include "scene_reader.hpp"

namespace hemivem {

namespace {

using detail::fmt;

std::string quote(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", c);
          out += b;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string scalar_text(const SceneScalar& v) { return v.is_expression() ? quote(v.expression) : fmt(v.value); }

/// The first `n` elements of an array (its components in `n` dimensions).
template <class T, std::size_t N>
std::vector<T> first(const std::array<T, N>& a, int n) {
  return std::vector<T>(a.begin(), a.begin() + std::min<std::ptrdiff_t>(n, static_cast<std::ptrdiff_t>(N)));
}

template <class Range, class F>
std::string list(const Range& r, F f) {
  std::string s = "[";
  bool first = true;
  for (const auto& x : r) {
    s += (first ? "" : ", ") + f(x);
    first = false;
  }
  return s + "]";
}

void write_selector(std::ostream& o, const BoundarySelector& b, int dims = 2) {
  if (!b.sides.empty()) o << "side = " << list(b.sides, quote) << "\n";
  if (!b.groups.empty()) o << "group = " << list(b.groups, quote) << "\n";
  if (!b.segments.empty())
    o << "segments = " << list(b.segments, [](const std::array<double, 4>& a) { return list(a, fmt); }) << "\n";
  o << "tolerance = " << fmt(b.tolerance) << "\n";
  if (b.points.empty()) return;
  const auto point = [dims](const std::array<double, 3>& x) { return list(first(x, dims), fmt); };
  o << "point = " << (b.points.size() == 1 ? point(b.points.front()) : list(b.points, point)) << "\n";
}


/// breakpoints and j, or j1 and j2, of a piecewise law (nothing for another law).
void write_pieces(std::ostream& o, const SceneLaw& law) {
  if (law.name != "piecewise") return;
  auto pieces = [](const std::vector<std::vector<double>>& p) {
    return list(p, [](const std::vector<double>& q) { return list(q, fmt); });
  };
  o << "breakpoints = " << list(law.breakpoints, fmt) << "\n";
  if (!law.j.empty()) {
    o << "j = " << pieces(law.j) << "\n";
    return;
  }
  o << "j1 = " << pieces(law.j1) << "\n";
  o << "j2 = " << pieces(law.j2) << "\n";
}

void write_mesh(std::ostream& o, const SceneMesh& m, const std::string& at = "") {
  o << "[" << at << "mesh]\n";
  if (!m.file.empty()) {
    o << "file = " << quote(m.file.generic_string()) << "\n";
    return;
  }
  o << "generator = " << quote(m.generator) << "\n";
  if (m.dimension == 3 && m.ny && m.nz)  // as given: [nx, ny, nz] reads back to the same scene
    o << "n = [" << m.n << ", " << *m.ny << ", " << *m.nz << "]\n";
  else if (m.generator == "polar" && m.ny)  // always [radial, around]
    o << "n = [" << m.n << ", " << *m.ny << "]\n";
  else
    o << "n = " << m.n_text() << "\n";
  o << "seed = " << m.seed << "\n";
  if (m.generator == "polar") {
    o << "center = " << list(m.center, fmt) << "\nradii = " << list(m.radii, fmt) << "\nangles = " << list(m.angles, fmt)
      << "\ngrading = " << fmt(m.grading) << "\n";
    if (m.focus) o << "focus = " << fmt(*m.focus) << "\n";
  } else if (m.dimension == 3)
    o << "domain = " << list(m.box, fmt) << "\n";
  else if (m.polygon.empty())
    o << "domain = " << list(m.domain, fmt) << "\n";
  else
    o << "domain = " << list(m.polygon, [](const std::array<double, 2>& p) { return list(p, fmt); }) << "\n";
}

void write_material(std::ostream& o, const SceneMaterial& m, int dimension, const std::string& at = "") {
  o << "\n[" << at << "material]\n";
  o << "E = " << fmt(m.young) << "\n";
  o << "nu = " << fmt(m.poisson) << "\n";
  if (dimension != 3) o << "model = " << quote(to_string(m.model)) << "\n";  // a solid has no plane model
  o << "stabilization = " << quote(to_string(m.stabilization)) << "\n";
  for (const auto& r : m.regions) {
    o << "\n[[" << at << "material.region]]\nid = " << r.region << "\nE = " << fmt(r.young) << "\nnu = " << fmt(r.poisson) << "\n";
    if (r.box) o << "box = " << list(*r.box, fmt) << "\n";
  }
}

/// [clamped] (when it selects anything) and each [[dirichlet]].
void write_dirichlet(std::ostream& o, const Scene& s, const std::string& at = "") {
  if (!s.clamped.empty()) {
    o << "\n[" << at << "clamped]\n";
    write_selector(o, s.clamped, s.dimension());
  }
  for (const auto& d : s.dirichlet) {
    o << "\n[[" << at << "dirichlet]]\n";
    write_selector(o, d.boundary, s.dimension());
    if (d.ux) o << "ux = " << scalar_text(*d.ux) << "\n";
    if (d.uy) o << "uy = " << scalar_text(*d.uy) << "\n";
    if (d.uz) o << "uz = " << scalar_text(*d.uz) << "\n";
  }
}

void write_loads(std::ostream& o, const Scene& s, const std::string& at = "") {
  o << "\n[" << at << "loads]\n";
  const int dims = s.dimension();
  o << "body_force = " << list(first(s.body_force, dims), scalar_text) << "\n";
  for (const auto& t : s.tractions) {
    o << "\n[[" << at << "loads.traction]]\n";
    write_selector(o, t.boundary);
    if (t.pressure) o << "pressure = " << scalar_text(*t.pressure) << "\n";
    else o << "value = " << list(first(t.value, dims), scalar_text) << "\n";
  }
}

void write_obstacle(std::ostream& o, const SceneObstacle& b, int dims) {
  o << "\n[contact.obstacle]\nshape = " << quote(b.shape) << "\n";
  if (b.shape == "plane")
    o << "point = " << list(first(b.point, dims), fmt) << "\nnormal = " << list(first(b.normal, dims), fmt) << "\n";
  if (b.shape == "circle" || b.shape == "sphere" || b.shape == "cylinder")
    o << "center = " << list(first(b.center, dims), fmt) << "\nradius = " << fmt(b.radius) << "\n";
  if (b.shape == "cylinder") o << "axis = " << list(b.axis, fmt) << "\n";
  if (b.shape == "polyline")
    o << "points = " << list(b.points, [](const std::array<double, 2>& q) { return list(q, fmt); }) << "\n";
  if (b.motion) o << "motion = " << list(first(*b.motion, dims), scalar_text) << "\n";
}

/// [contact] (or one table of [[contact]], `in_array`) and its [contact.obstacle],
/// [contact.parameters] and [contact.friction].
void write_contact(std::ostream& o, const SceneContact& c, bool in_array, int dims) {
  o << (in_array ? "\n[[contact]]\n" : "\n[contact]\n");
  if (!c.name.empty()) o << "name = " << quote(c.name) << "\n";
  if (c.body.empty()) {
    write_selector(o, c.boundary);
  } else {
    // a scene of several bodies names a part's sides and groups after its body
    BoundarySelector named = c.boundary;
    for (auto& x : named.sides) x = c.body + "." + x;
    for (auto& x : named.groups) x = c.body + "." + x;
    write_selector(o, named);
  }
  if (c.against) {
    const std::string name = c.against->sides.empty() ? c.against->groups.front() : c.against->sides.front();
    o << "against = " << quote(c.against_body + "." + name) << "\n";
    if (c.pairing != BodyPairing::vertex) o << "pairing = " << quote(to_string(c.pairing)) << "\n";
  }
  o << "law = " << quote(c.law.name) << "\n";
  write_pieces(o, c.law);
  // a bilateral contact uses no gap: written only when it is not the default
  if (!c.obstacle && (c.constraint != ConstraintKind::bilateral || !(c.gap == SceneContact{}.gap)))
    o << "gap = " << scalar_text(c.gap) << "\n";
  o << "constraint = " << quote(to_string(c.constraint)) << "\n";
  o << "law_origin = " << quote(c.law_origin) << "\n";
  if (c.obstacle) write_obstacle(o, *c.obstacle, dims);
  if (!c.law.parameters.empty()) {
    o << "\n[contact.parameters]\n";
    for (const auto& [k, v] : c.law.parameters) o << k << " = " << fmt(v) << "\n";
  }
  if (c.friction) {
    o << "\n[contact.friction]\nlaw = " << quote(c.friction->name) << "\n";
    for (const auto& [k, v] : c.friction->parameters)
      if (k != "bound" || c.friction->bound_table.empty()) o << k << " = " << fmt(v) << "\n";
    if (!c.friction->bound_table.empty())
      o << "bound = " << list(c.friction->bound_table, [](const std::array<double, 2>& p) { return list(p, fmt); })
        << "\n";
    write_pieces(o, *c.friction);
  }
}

void write_solver(std::ostream& o, const SceneSolver& v) {
  o << "\n[solver]\n";
  o << "linear = " << quote(v.linear) << "\n";
  o << "minimizer = " << quote(v.minimizer) << "\n";
  o << "tolerance = " << fmt(v.tolerance) << "\n";
  o << "max_iterations = " << v.max_iterations << "\n";
  o << "search = " << quote(v.search) << "\n";
  o << "max_starts = " << v.max_starts << "\n";
  o << "time_budget = " << fmt(v.time_budget) << "\n";
  o << "seed = " << v.seed << "\n";
  o << "search_engines = " << list(v.search_engines, quote) << "\n";
  o << "grid_sequence = "
    << (v.grid_sequence == SceneSolver::grid_sequence_auto ? quote("auto") : std::to_string(v.grid_sequence)) << "\n";
  if (!v.parameters.empty()) {
    o << "\n[solver.parameters]\n";
    for (const auto& [k, x] : v.parameters) o << k << " = " << fmt(x) << "\n";
  }
}

}  // namespace

std::string to_toml(const Scene& s) {
  std::ostringstream o;
  o << "# hemivem scene (resolved: every key written)\n";
  o << "schema_version = " << s.schema_version << "\n";
  o << "title = " << quote(s.title) << "\n\n";
  if (s.bodies.empty()) {
    write_mesh(o, s.mesh);
    write_material(o, s.material, s.dimension());
    write_dirichlet(o, s);
    write_loads(o, s);
  }
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    o << (b == 0 ? "" : "\n") << "[[body]]\nname = " << quote(s.bodies[b].name) << "\n\n";
    const Scene one = body_scene(s, b);
    write_mesh(o, one.mesh, "body.");
    write_material(o, one.material, one.dimension(), "body.");
    write_dirichlet(o, one, "body.");
    write_loads(o, one, "body.");
  }
  for (const SceneContact& c : contact_parts(s)) write_contact(o, c, !s.more_contact.empty(), s.dimension());
  write_solver(o, s.solver);
  if (s.adapt) {
    o << "\n[adapt]\n";
    o << "target = " << fmt(s.adapt->target) << "\n";
    o << "max_unknowns = " << s.adapt->max_unknowns << "\n";
    o << "max_steps = " << s.adapt->max_steps << "\n";
    o << "fraction = " << fmt(s.adapt->fraction) << "\n";
  }
  if (s.path) {
    o << "\n[path]\n";
    if (s.path->t.empty()) o << "steps = " << s.path->steps << "\n";
    else o << "t = " << list(s.path->t, fmt) << "\n";
    o << "frames = " << s.path->frames << "\n";
  }
  o << "\n[output]\n";
  o << "write = " << list(s.outputs, quote) << "\n";
  o << "figure_format = " << list(s.figure_formats, quote) << "\n";
  return o.str();
}

void write_scene(const std::filesystem::path& path, const Scene& scene) {
  const std::string text = to_toml(scene);
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace hemivem
