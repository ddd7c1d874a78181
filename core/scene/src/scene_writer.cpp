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

void write_selector(std::ostream& o, const BoundarySelector& b) {
  if (!b.sides.empty()) o << "side = " << list(b.sides, quote) << "\n";
  if (!b.groups.empty()) o << "group = " << list(b.groups, quote) << "\n";
  if (!b.segments.empty())
    o << "segments = " << list(b.segments, [](const std::array<double, 4>& a) { return list(a, fmt); }) << "\n";
  o << "tolerance = " << fmt(b.tolerance) << "\n";
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

}  // namespace

std::string to_toml(const Scene& s) {
  std::ostringstream o;
  o << "# hemivem scene (resolved: every key written)\n";
  o << "schema_version = " << s.schema_version << "\n";
  o << "title = " << quote(s.title) << "\n\n";
  o << "[mesh]\n";
  if (!s.mesh.file.empty()) {
    o << "file = " << quote(s.mesh.file.generic_string()) << "\n";
  } else {
    o << "generator = " << quote(s.mesh.generator) << "\n";
    o << "n = " << s.mesh.cells().text() << "\n";
    o << "seed = " << s.mesh.seed << "\n";
    if (s.mesh.polygon.empty())
      o << "domain = " << list(s.mesh.domain, fmt) << "\n";
    else
      o << "domain = " << list(s.mesh.polygon, [](const std::array<double, 2>& p) { return list(p, fmt); }) << "\n";
  }
  o << "\n[material]\n";
  o << "E = " << fmt(s.material.young) << "\n";
  o << "nu = " << fmt(s.material.poisson) << "\n";
  o << "model = " << quote(to_string(s.material.model)) << "\n";
  o << "stabilization = " << quote(to_string(s.material.stabilization)) << "\n";
  for (const auto& r : s.material.regions) {
    o << "\n[[material.region]]\nid = " << r.region << "\nE = " << fmt(r.young) << "\nnu = " << fmt(r.poisson) << "\n";
    if (r.box) o << "box = " << list(*r.box, fmt) << "\n";
  }
  if (!s.clamped.empty()) {
    o << "\n[clamped]\n";
    write_selector(o, s.clamped);
  }
  for (const auto& d : s.dirichlet) {
    o << "\n[[dirichlet]]\n";
    write_selector(o, d.boundary);
    if (d.ux) o << "ux = " << scalar_text(*d.ux) << "\n";
    if (d.uy) o << "uy = " << scalar_text(*d.uy) << "\n";
  }
  o << "\n[loads]\n";
  o << "body_force = " << list(s.body_force, scalar_text) << "\n";
  for (const auto& t : s.tractions) {
    o << "\n[[loads.traction]]\n";
    write_selector(o, t.boundary);
    if (t.pressure) o << "pressure = " << scalar_text(*t.pressure) << "\n";
    else o << "value = " << list(t.value, scalar_text) << "\n";
  }
  if (s.contact) {
    const auto& c = *s.contact;
    o << "\n[contact]\n";
    write_selector(o, c.boundary);
    o << "law = " << quote(c.law.name) << "\n";
    write_pieces(o, c.law);
    if (!c.obstacle) o << "gap = " << scalar_text(c.gap) << "\n";
    o << "constraint = " << quote(to_string(c.constraint)) << "\n";
    if (c.obstacle) {
      const auto& b = *c.obstacle;
      o << "\n[contact.obstacle]\nshape = " << quote(b.shape) << "\n";
      if (b.shape == "plane") o << "point = " << list(b.point, fmt) << "\nnormal = " << list(b.normal, fmt) << "\n";
      if (b.shape == "circle") o << "center = " << list(b.center, fmt) << "\nradius = " << fmt(b.radius) << "\n";
      if (b.shape == "polyline")
        o << "points = " << list(b.points, [](const std::array<double, 2>& q) { return list(q, fmt); }) << "\n";
    }
    if (!c.law.parameters.empty()) {
      o << "\n[contact.parameters]\n";
      for (const auto& [k, v] : c.law.parameters) o << k << " = " << fmt(v) << "\n";
    }
    if (c.friction) {
      o << "\n[contact.friction]\nlaw = " << quote(c.friction->name) << "\n";
      for (const auto& [k, v] : c.friction->parameters) o << k << " = " << fmt(v) << "\n";
      write_pieces(o, *c.friction);
    }
  }
  o << "\n[solver]\n";
  o << "linear = " << quote(s.solver.linear) << "\n";
  o << "minimizer = " << quote(s.solver.minimizer) << "\n";
  o << "tolerance = " << fmt(s.solver.tolerance) << "\n";
  o << "max_iterations = " << s.solver.max_iterations << "\n";
  o << "search = " << quote(s.solver.search) << "\n";
  o << "max_starts = " << s.solver.max_starts << "\n";
  o << "time_budget = " << fmt(s.solver.time_budget) << "\n";
  o << "seed = " << s.solver.seed << "\n";
  o << "search_engines = " << list(s.solver.search_engines, quote) << "\n";
  if (!s.solver.parameters.empty()) {
    o << "\n[solver.parameters]\n";
    for (const auto& [k, v] : s.solver.parameters) o << k << " = " << fmt(v) << "\n";
  }
  o << "\n[output]\n";
  o << "write = " << list(s.outputs, quote) << "\n";
  return o.str();
}

void write_scene(const std::filesystem::path& path, const Scene& scene) {
  const std::string text = to_toml(scene);
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace hemivem
