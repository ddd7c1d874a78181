#include <hemivem/scene.hpp>

#include <hemivem/expression.hpp>
#include <hemivem/obstacle.hpp>
#include <hemivem/resources.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include <hemivem/atomic_file.hpp>
#include <hemivem/error.hpp>
#include <hemivem/gmsh.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/mesh_io.hpp>
#include <hemivem/piecewise_law.hpp>

#include "default_scene_text.hpp"
#include "text_lines.hpp"

namespace hemivem {

namespace {

// A vertex count as an integer when small enough to read, else in scientific notation.
std::string count_text(double v) {
  if (v < 1e9) return std::to_string(static_cast<long long>(std::llround(v)));
  std::ostringstream o;
  o << std::setprecision(2) << std::scientific << v;
  return o.str();
}

std::string fmt(double v);

const std::vector<std::string> kSides{"left", "right", "top", "bottom"};

std::string lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return r;
}

std::size_t edit_distance(std::string_view a0, std::string_view b0) {
  const std::string a = lower(a0), b = lower(b0);
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date/time";
  }
}

/// Reads one table of the scene: unknown keys are rejected on construction; every read
/// records the key's line in the scene and checks its type.
class TableReader {
 public:
  TableReader(Scene& scene, const toml::table& table, std::string path, const std::vector<std::string>& allowed)
      : scene_(scene), table_(table), path_(std::move(path)) {
    const toml::node* worst = nullptr;
    std::string worst_key;
    for (const auto& [k, v] : table_) {
      const std::string key(k.str());
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      if (!worst || v.source().begin.line < worst->source().begin.line) worst = &v, worst_key = key;
    }
    if (worst) {
      std::string msg = "unknown key '" + worst_key + "' in [" + (path_.empty() ? "root" : path_) + "]";
      msg += did_you_mean(worst_key, allowed);
      throw InputError(msg, at(*worst));
    }
    if (!path_.empty() && table_.source().begin.line > 0) scene_.lines[path_] = static_cast<int>(table_.source().begin.line);
  }

  std::string key_path(std::string_view key) const { return path_.empty() ? std::string(key) : path_ + "." + std::string(key); }
  std::string at(const toml::node& n) const {
    const auto line = n.source().begin.line;
    return line > 0 ? scene_.source + ":" + std::to_string(line) : scene_.source;
  }
  [[noreturn]] void fail(std::string_view key, const toml::node& n, const std::string& message) const {
    throw InputError(key_path(key) + ": " + message, at(n));
  }
  [[noreturn]] void fail_type(std::string_view key, const toml::node& n, const std::string& expected) const {
    fail(key, n, "expected " + expected + ", got " + type_name(n));
  }

  const toml::node* find(std::string_view key) {
    const toml::node* n = table_.get(key);
    if (n) scene_.lines[key_path(key)] = static_cast<int>(n->source().begin.line);
    return n;
  }
  bool has(std::string_view key) const { return table_.get(key) != nullptr; }

  double as_number(std::string_view key, const toml::node& n) const {
    double v = 0.0;
    if (auto i = n.as_integer()) v = static_cast<double>(i->get());
    else if (auto f = n.as_floating_point()) v = f->get();
    else fail_type(key, n, "a number");
    if (!std::isfinite(v)) fail(key, n, "expected a finite number");
    return v;
  }
  std::optional<double> number(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    return as_number(key, *n);
  }
  /// A number, or a string holding an expression in x and y (parsed here, so that a syntax
  /// error names the key's line).
  SceneScalar as_scalar(std::string_view key, const toml::node& n, const std::string& element = "") const {
    if (const auto* text = n.as_string()) {
      try {
        (void)ScalarExpression::parse(text->get());
      } catch (const InputError& e) {
        fail(key, n, element + e.detail());
      }
      return SceneScalar{0.0, text->get()};
    }
    if (!n.is_integer() && !n.is_floating_point())
      fail(key, n, element + "expected a number or an expression in x and y (a string), got " + type_name(n));
    return SceneScalar{as_number(key, n), {}};
  }
  std::optional<SceneScalar> scalar(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    return as_scalar(key, *n);
  }
  /// An array of N numbers or expressions.
  template <std::size_t N>
  std::optional<std::array<SceneScalar, N>> scalars(std::string_view key, const std::string& shape) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    const auto* a = n->as_array();
    if (!a) fail_type(key, *n, "an array " + shape + " of numbers or expressions");
    if (a->size() != N)
      fail(key, *n, "expected an array " + shape + " of " + std::to_string(N) + " numbers or expressions, got " +
                        std::to_string(a->size()));
    std::array<SceneScalar, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = as_scalar(key, (*a)[i], "element " + std::to_string(i) + ": ");
    return out;
  }
  std::optional<std::int64_t> integer(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    if (auto i = n->as_integer()) return i->get();
    fail_type(key, *n, "an integer");
  }
  std::optional<std::string> string(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    if (auto s = n->as_string()) return s->get();
    fail_type(key, *n, "a string");
  }
  /// A string or an array of strings.
  std::optional<std::vector<std::string>> strings(std::string_view key, bool allow_single) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    if (auto s = n->as_string(); s && allow_single) return std::vector<std::string>{s->get()};
    const auto* a = n->as_array();
    if (!a) fail_type(key, *n, allow_single ? "a string or an array of strings" : "an array of strings");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const auto* s = (*a)[i].as_string();
      if (!s) fail(key, (*a)[i], "element " + std::to_string(i) + ": expected a string, got " + type_name((*a)[i]));
      out.push_back(s->get());
    }
    return out;
  }
  std::vector<double> numbers_of(std::string_view key, const toml::node& n, const std::string& what) const {
    const auto* a = n.as_array();
    if (!a) fail_type(key, n, what);
    std::vector<double> out;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const toml::node& e = (*a)[i];
      if (!e.is_integer() && !e.is_floating_point())
        fail(key, e, "element " + std::to_string(i) + ": expected a number, got " + type_name(e));
      out.push_back(as_number(key, e));
    }
    return out;
  }
  std::optional<std::vector<double>> numbers(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    return numbers_of(key, *n, "an array of numbers");
  }
  template <std::size_t N>
  std::optional<std::array<double, N>> fixed(std::string_view key, const std::string& shape) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    const auto v = numbers_of(key, *n, "an array " + shape);
    if (v.size() != N)
      fail(key, *n, "expected an array " + shape + " of " + std::to_string(N) + " numbers, got " + std::to_string(v.size()));
    std::array<double, N> out{};
    std::copy(v.begin(), v.end(), out.begin());
    return out;
  }
  /// An array of arrays of numbers.
  std::optional<std::vector<std::vector<double>>> matrix(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return std::nullopt;
    const auto* a = n->as_array();
    if (!a) fail_type(key, *n, "an array of arrays of numbers");
    std::vector<std::vector<double>> out;
    for (std::size_t i = 0; i < a->size(); ++i) out.push_back(numbers_of(key, (*a)[i], "an array of arrays of numbers"));
    return out;
  }
  /// An array of [x, y] arrays.
  std::optional<std::vector<std::array<double, 2>>> points(std::string_view key) {
    const auto m = matrix(key);
    if (!m) return std::nullopt;
    std::vector<std::array<double, 2>> out;
    for (std::size_t i = 0; i < m->size(); ++i) {
      if ((*m)[i].size() != 2)
        fail(key, node(key), "point " + std::to_string(i) + ": expected [x, y], got " + std::to_string((*m)[i].size()) +
                                 " numbers");
      out.push_back({(*m)[i][0], (*m)[i][1]});
    }
    return out;
  }
  const toml::table* table(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return nullptr;
    if (auto t = n->as_table()) return t;
    fail_type(key, *n, "a table");
  }
  const toml::array* array_of_tables(std::string_view key) {
    const toml::node* n = find(key);
    if (!n) return nullptr;
    const auto* a = n->as_array();
    if (!a || !a->is_array_of_tables()) fail_type(key, *n, "an array of tables ([[" + key_path(key) + "]])");
    return a;
  }
  const toml::node& node(std::string_view key) const { return *table_.get(key); }
  const toml::table& self() const { return table_; }
  const std::string& path() const { return path_; }
  Scene& scene() { return scene_; }

 private:
  Scene& scene_;
  const toml::table& table_;
  std::string path_;
};

const std::vector<std::string> kSelectorKeys{"side", "group", "segments", "tolerance"};

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

BoundarySelector read_selector(TableReader& r, bool required) {
  BoundarySelector s;
  s.sides.clear();
  if (auto v = r.strings("side", true)) {
    for (const auto& side : *v) {
      if (std::find(kSides.begin(), kSides.end(), lower(side)) == kSides.end())
        r.fail("side", r.node("side"),
               "unknown side '" + side + "'" + did_you_mean(side, kSides) + " (expected one of: " + join(kSides) + ")");
      s.sides.push_back(lower(side));
    }
  }
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
  if (required && s.empty())
    throw InputError(r.path() + ": no boundary given; set side, group or segments", r.at(r.self()));
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

double param(const SceneLaw& law, const std::string& name, double fallback) {
  auto it = law.parameters.find(name);
  return it == law.parameters.end() ? fallback : it->second;
}

std::shared_ptr<const ContactLaw> make_law(const SceneLaw& law) {
  const std::string n = lower(law.name);
  if (n == "piecewise") {
    std::vector<Polynomial> j1(law.j1.begin(), law.j1.end()), j2(law.j2.begin(), law.j2.end());
    return std::make_shared<PiecewisePolynomialLaw>("piecewise", law.breakpoints, j1, j2);
  }
  if (n == "linear") return linear_law(param(law, "stiffness", 100.0));
  if (n == "kinked") return kinked_law(param(law, "sigma", 0.3), param(law, "stiffness", 100.0));
  if (n == "sawtooth")
    return sawtooth_law(param(law, "stiffness", 100.0), param(law, "r1", 0.01), param(law, "residual", 0.2),
                        param(law, "r2", 0.02));
  return make_contact_law(n);
}

std::vector<std::string> law_names() {
  auto v = contact_law_names();
  v.push_back("piecewise");
  return v;
}

Obstacle make_obstacle(const SceneObstacle& o) {
  Obstacle b;
  b.shape = obstacle_shape_from_string(o.shape);
  b.point = Vec2(o.point[0], o.point[1]);
  b.normal = Vec2(o.normal[0], o.normal[1]);
  b.center = Vec2(o.center[0], o.center[1]);
  b.radius = o.radius;
  for (const auto& q : o.points) b.points.emplace_back(q[0], q[1]);
  return b;
}

SceneContact read_contact(TableReader& r) {
  SceneContact c;
  c.boundary = read_selector(r, true);
  if (auto law = r.string("law")) {
    check_name(r, "law", *law, law_names(), "contact law");
    c.law.name = lower(*law);
  }
  const bool piecewise = c.law.name == "piecewise";
  for (const char* k : {"breakpoints", "j1", "j2"})
    if (r.has(k) && !piecewise) r.fail(k, r.node(k), "only used with law = \"piecewise\" (the law is '" + c.law.name + "')");
  if (piecewise) {
    for (const char* k : {"breakpoints", "j1", "j2"})
      if (!r.has(k)) r.fail("law", r.node("law"), "law = \"piecewise\" needs breakpoints, j1 and j2");
    c.law.breakpoints = *r.numbers("breakpoints");
    c.law.j1 = *r.matrix("j1");
    c.law.j2 = *r.matrix("j2");
    for (const char* k : {"j1", "j2"}) {
      const auto& pieces = std::string(k) == "j1" ? c.law.j1 : c.law.j2;
      if (pieces.size() != c.law.breakpoints.size() + 1)
        r.fail(k, r.node(k),
               "expected " + std::to_string(c.law.breakpoints.size() + 1) + " pieces (one more than the breakpoints), got " +
                   std::to_string(pieces.size()));
    }
  }
  if (const toml::table* p = r.table("parameters")) {
    const auto& allowed = law_parameter_names().at(c.law.name);
    for (const auto& [k, v] : *p) {  // a parameter of another law: name the law
      const std::string key(k.str());
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string owners;
      for (const auto& [law, names] : law_parameter_names())
        if (std::find(names.begin(), names.end(), key) != names.end()) owners += (owners.empty() ? "" : ", ") + law;
      if (owners.empty()) continue;  // unknown to every law: the reader below suggests a name
      r.fail("parameters", v, "'" + key + "' is a parameter of law " + owners + ", not of law '" + c.law.name + "'" +
                                   (allowed.empty() ? " (which has none)" : " (which has: " + join(allowed) + ")"));
    }
    TableReader pr(r.scene(), *p, r.key_path("parameters"), allowed);
    for (const auto& name : allowed)
      if (auto v = pr.number(name)) c.law.parameters[name] = *v;
  }
  try {
    (void)make_law(c.law);
  } catch (const InputError& e) {
    r.fail("law", r.has("law") ? r.node("law") : static_cast<const toml::node&>(r.self()), e.detail());
  }
  if (auto g = r.scalar("gap")) {
    if (!g->is_expression() && g->value < 0.0) r.fail("gap", r.node("gap"), "must be >= 0, got " + fmt(g->value));
    c.gap = *g;
  }
  if (const toml::table* o = r.table("obstacle")) {
    if (r.has("gap")) r.fail("gap", r.node("gap"), "not used with [contact.obstacle]; give either a gap or an obstacle");
    TableReader ob(r.scene(), *o, r.key_path("obstacle"), {"shape", "point", "normal", "center", "radius", "points"});
    SceneObstacle so;
    if (auto shape = ob.string("shape")) so.shape = lower(*shape);
    try {
      (void)obstacle_shape_from_string(so.shape);
    } catch (const InputError& e) {
      ob.fail("shape", ob.node("shape"), e.detail());
    }
    const std::map<std::string, std::vector<std::string>> keys{
        {"plane", {"point", "normal"}}, {"circle", {"center", "radius"}}, {"polyline", {"points"}}};
    const auto it = keys.find(so.shape);
    for (const char* k : {"point", "normal", "center", "radius", "points"}) {
      const bool used = std::find(it->second.begin(), it->second.end(), k) != it->second.end();
      if (!used && ob.has(k)) ob.fail(k, ob.node(k), "not used by a " + so.shape + " obstacle");
      if (used && !ob.has(k))
        throw InputError(ob.path() + ": a " + so.shape + " obstacle needs '" + k + "'", ob.at(ob.self()));
    }
    if (auto v = ob.fixed<2>("point", "[x, y]")) so.point = *v;
    if (auto v = ob.fixed<2>("normal", "[nx, ny]")) so.normal = *v;
    if (auto v = ob.fixed<2>("center", "[x, y]")) so.center = *v;
    if (auto v = ob.number("radius")) so.radius = *v;
    if (auto v = ob.points("points")) so.points = *v;
    const std::string defect = make_obstacle(so).defect();
    if (!defect.empty()) {
      const char* key = so.shape == "plane" ? "normal" : (so.shape == "circle" ? "radius" : "points");
      ob.fail(key, ob.node(key), defect);
    }
    c.obstacle = so;
    c.constraint = ConstraintKind::one_sided;  // unless the scene says otherwise
  }
  if (auto k = r.string("constraint")) {
    try {
      c.constraint = constraint_kind_from_string(*k);
    } catch (const InputError&) {
      r.fail("constraint", r.node("constraint"), "unknown constraint '" + *k + "'; expected one of: none, one-sided, box");
    }
  }
  return c;
}

Scene scene_from_table(const toml::table& root, std::string source, const std::filesystem::path& base) {
  Scene s;
  s.source = std::move(source);
  s.lines.clear();
  TableReader r(s, root, "",
                {"schema_version", "title", "mesh", "material", "clamped", "dirichlet", "loads", "contact", "solver", "output"});
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

  if (const toml::table* t = r.table("mesh")) {
    TableReader m(s, *t, "mesh", {"generator", "file", "n", "seed", "domain"});
    if (m.has("file")) {
      for (const char* k : {"generator", "n", "seed", "domain"})
        if (m.has(k)) m.fail(k, m.node(k), "not used with mesh.file; give either a generator or a file");
      const auto f = *m.string("file");
      if (f.empty()) m.fail("file", m.node("file"), "empty path");
      std::filesystem::path p(f);
      if (p.is_relative()) p = base / p;
      p = p.lexically_normal();
      const std::string ext = lower(p.extension().string());
      if (ext != ".poly2d" && ext != ".msh")
        m.fail("file", m.node("file"), "unknown mesh format '" + p.extension().string() + "'; expected .poly2d or .msh");
      s.mesh.file = p;
    }
    if (auto g = m.string("generator")) {
      check_name(m, "generator", *g, mesh_generator_names(), "mesh generator");
      s.mesh.generator = lower(*g);
    }
    if (auto n = m.integer("n")) {
      if (*n < 1 || *n > 10000000) m.fail("n", m.node("n"), "must be between 1 and 10000000, got " + std::to_string(*n));
      s.mesh.n = static_cast<int>(*n);
    }
    if (auto seed = m.integer("seed")) {
      if (*seed < 0) m.fail("seed", m.node("seed"), "must be >= 0, got " + std::to_string(*seed));
      s.mesh.seed = *seed;
    }
    const toml::array* domain = m.has("domain") ? m.node("domain").as_array() : nullptr;
    if (domain && !domain->empty() && (*domain)[0].is_array()) {
      s.mesh.polygon = *m.points("domain");
      PolygonDomain poly;
      for (const auto& p : s.mesh.polygon) poly.corners.emplace_back(p[0], p[1]);
      const std::string defect = polygon_domain_defect(poly);
      if (!defect.empty()) m.fail("domain", m.node("domain"), "the polygon " + defect);
      if (s.mesh.generator != "voronoi" && s.mesh.generator != "triangles")
        m.fail("domain", m.node("domain"),
               "a polygon domain needs generator = \"voronoi\" or \"triangles\" (the generator is \"" +
                   s.mesh.generator + "\")");
    } else if (auto d = m.fixed<4>("domain", "[x0, x1, y0, y1] or a polygon [[x0, y0], [x1, y1], ...]")) {
      if (!((*d)[0] < (*d)[1] && (*d)[2] < (*d)[3])) m.fail("domain", m.node("domain"), "needs x0 < x1 and y0 < y1");
      s.mesh.domain = *d;
    }
  }

  if (const toml::table* t = r.table("material")) {
    TableReader m(s, *t, "material", {"E", "nu", "model", "stabilization", "region"});
    if (auto e = m.number("E")) {
      if (!(*e > 0.0)) m.fail("E", m.node("E"), "must be > 0, got " + fmt(*e));
      s.material.young = *e;
    }
    if (auto nu = m.number("nu")) {
      if (!(*nu > -1.0 && *nu < 0.5)) m.fail("nu", m.node("nu"), "must lie in (-1, 0.5), got " + fmt(*nu));
      s.material.poisson = *nu;
    }
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
        if (auto b = g.fixed<4>("box", "[x0, x1, y0, y1]")) {
          if (!((*b)[0] < (*b)[1] && (*b)[2] < (*b)[3])) g.fail("box", g.node("box"), "needs x0 < x1 and y0 < y1");
          rm.box = *b;
        }
        s.material.regions.push_back(rm);
      }
    }
  }

  if (const toml::table* t = r.table("clamped")) {
    TableReader c(s, *t, "clamped", kSelectorKeys);
    s.clamped = read_selector(c, true);
  }
  if (const toml::array* d = r.array_of_tables("dirichlet")) {
    if (!r.has("clamped")) s.clamped = BoundarySelector{{}, {}, {}, 1e-8};  // only what the scene prescribes
    for (std::size_t i = 0; i < d->size(); ++i) {
      TableReader g(s, *(*d)[i].as_table(), "dirichlet[" + std::to_string(i) + "]", with_selector({"value", "ux", "uy"}));
      SceneDirichlet sd;
      sd.boundary = read_selector(g, true);
      if (auto v = g.scalars<2>("value", "[ux, uy]")) {
        for (const char* k : {"ux", "uy"})
          if (g.has(k)) g.fail(k, g.node(k), "not used with value = [ux, uy]; give either value or ux and/or uy");
        sd.ux = (*v)[0];
        sd.uy = (*v)[1];
      }
      if (auto v = g.scalar("ux")) sd.ux = *v;
      if (auto v = g.scalar("uy")) sd.uy = *v;
      if (!sd.ux && !sd.uy)
        throw InputError(g.path() + ": no displacement given; set value = [ux, uy], or ux or uy (a roller)",
                         g.at(g.self()));
      s.dirichlet.push_back(sd);
    }
  }

  if (const toml::table* t = r.table("loads")) {
    TableReader l(s, *t, "loads", {"body_force", "traction"});
    if (auto f = l.scalars<2>("body_force", "[fx, fy]")) s.body_force = *f;
    s.tractions.clear();
    if (const toml::array* tr = l.array_of_tables("traction")) {
      for (std::size_t i = 0; i < tr->size(); ++i) {
        TableReader g(s, *(*tr)[i].as_table(), "loads.traction[" + std::to_string(i) + "]",
                      with_selector({"value", "pressure"}));
        SceneTraction st;
        st.boundary = read_selector(g, true);
        const auto v = g.scalars<2>("value", "[tx, ty]");
        st.pressure = g.scalar("pressure");
        if (v && st.pressure)
          g.fail("pressure", g.node("pressure"), "not used with value = [tx, ty]; give either value or pressure");
        if (!v && !st.pressure)
          throw InputError(g.path() + ": missing key 'value' (a traction [tx, ty]) or 'pressure' (along the inward normal)",
                           g.at(g.self()));
        if (v) st.value = *v;
        s.tractions.push_back(st);
      }
    }
  } else {
    s.tractions.clear();
    s.body_force = {};
  }

  s.contact.reset();
  if (const toml::table* t = r.table("contact")) {
    TableReader c(s, *t, "contact",
                  with_selector({"law", "parameters", "breakpoints", "j1", "j2", "gap", "obstacle", "constraint"}));
    s.contact = read_contact(c);
  }

  if (const toml::table* t = r.table("solver")) {
    TableReader v(s, *t, "solver", {"linear", "minimizer", "tolerance", "max_iterations", "parameters"});
    if (auto x = v.string("linear")) {
      if (x->empty()) v.fail("linear", v.node("linear"), "empty name");
      s.solver.linear = *x;
    }
    if (auto x = v.string("minimizer")) {
      if (x->empty()) v.fail("minimizer", v.node("minimizer"), "empty name");
      s.solver.minimizer = *x;
    }
    if (auto x = v.number("tolerance")) {
      if (!(*x > 0.0 && *x < 1.0)) v.fail("tolerance", v.node("tolerance"), "must be in (0, 1), got " + fmt(*x));
      s.solver.tolerance = *x;
    }
    if (auto x = v.integer("max_iterations")) {
      if (*x < 1 || *x > std::numeric_limits<int>::max())
        v.fail("max_iterations", v.node("max_iterations"),
               "must be between 1 and " + std::to_string(std::numeric_limits<int>::max()) + ", got " + std::to_string(*x));
      s.solver.max_iterations = static_cast<int>(*x);
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

  if (const toml::table* t = r.table("output")) {
    TableReader o(s, *t, "output", {"write"});
    if (auto w = o.strings("write", false)) {
      s.outputs.clear();
      for (const auto& x : *w) {
        const auto& valid = scene_output_names();
        if (std::find(valid.begin(), valid.end(), lower(x)) == valid.end())
          o.fail("write", o.node("write"),
                 "unknown output '" + x + "'" + did_you_mean(x, valid) + " (expected any of: " + join(valid) + ")");
        if (std::find(s.outputs.begin(), s.outputs.end(), lower(x)) == s.outputs.end()) s.outputs.push_back(lower(x));
      }
    }
  }
  return s;
}

toml::table parse_toml(std::string_view text, const std::string& name) {
  try {
    return toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError("syntax error: " + std::string(e.description()),
                     name + ":" + std::to_string(b.line) + ":" + std::to_string(b.column));
  }
}

std::filesystem::path base_folder(const std::string& name) {
  std::filesystem::path p(name);
  std::filesystem::path parent = p.parent_path();
  if (parent.empty()) parent = std::filesystem::current_path();
  return std::filesystem::absolute(parent);
}

// ---- writing ----

std::string fmt(double v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, end);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // keep it a TOML float
  return s;
}

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

}  // namespace

std::string did_you_mean(std::string_view key, const std::vector<std::string>& valid) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& v : valid) {
    std::size_t d = edit_distance(lower(key), lower(v));
    const std::string k = lower(key), w = lower(v);
    if (k.size() >= 2 && (w.rfind(k, 0) == 0 || k.rfind(w, 0) == 0)) d = std::min<std::size_t>(d, 1);
    if (d < best_d) best_d = d, best = v;
  }
  if (best.empty() || best_d > std::max<std::size_t>(2, key.size() / 3)) return {};
  return "; did you mean '" + best + "'?";
}

const std::vector<std::string>& scene_output_names() {
  static const std::vector<std::string> names{"vtu",         "contact-csv", "displacement-csv", "history-csv",
                                              "result-json", "u-nu-png",    "deformed-png"};
  return names;
}

std::string Scene::where(const std::string& key) const {
  auto it = lines.find(key);
  if (it == lines.end() || it->second <= 0) return source;
  return source + ":" + std::to_string(it->second);
}

bool operator==(const Scene& a, const Scene& b) {
  return a.schema_version == b.schema_version && a.title == b.title && a.mesh == b.mesh && a.material == b.material &&
         a.clamped == b.clamped && a.dirichlet == b.dirichlet && a.body_force == b.body_force &&
         a.tractions == b.tractions && a.contact == b.contact &&
         a.solver == b.solver && a.outputs == b.outputs;
}

Scene parse_scene_string(std::string_view text, std::string name) {
  const toml::table root = parse_toml(text, name);
  return scene_from_table(root, name, base_folder(name));
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
    o << "n = " << s.mesh.n << "\n";
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
    if (c.law.name == "piecewise") {
      o << "breakpoints = " << list(c.law.breakpoints, fmt) << "\n";
      auto pieces = [](const std::vector<std::vector<double>>& p) {
        return list(p, [](const std::vector<double>& q) { return list(q, fmt); });
      };
      o << "j1 = " << pieces(c.law.j1) << "\n";
      o << "j2 = " << pieces(c.law.j2) << "\n";
    }
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
  }
  o << "\n[solver]\n";
  o << "linear = " << quote(s.solver.linear) << "\n";
  o << "minimizer = " << quote(s.solver.minimizer) << "\n";
  o << "tolerance = " << fmt(s.solver.tolerance) << "\n";
  o << "max_iterations = " << s.solver.max_iterations << "\n";
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

namespace {

/// One "dotted.key=value" override: the key, its path ("name[i]" selects element i of an
/// array of tables) and the value in TOML syntax (a bare word is a string).
struct Override {
  std::string key;
  std::vector<std::pair<std::string, int>> parts;
  toml::table holder;  ///< the value as "v"
  std::string where() const { return "--set " + key; }
};

Override parse_override(std::string_view key_eq_value) {
  const auto eq = key_eq_value.find('=');
  if (eq == std::string_view::npos)
    throw InputError("expected key=value, got '" + std::string(key_eq_value) + "'", "--set");
  auto trim = [](std::string_view v) {
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.front()))) v.remove_prefix(1);
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back()))) v.remove_suffix(1);
    return v;
  };
  Override o;
  o.key = std::string(trim(key_eq_value.substr(0, eq)));
  const std::string value(trim(key_eq_value.substr(eq + 1)));
  if (o.key.empty()) throw InputError("empty key", "--set");
  std::size_t start = 0;
  while (start <= o.key.size()) {
    const auto dot = o.key.find('.', start);
    std::string part = o.key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    int index = -1;
    if (auto lb = part.find('['); lb != std::string::npos) {
      if (part.back() != ']') throw InputError("bad index in key '" + o.key + "'", o.where());
      try {
        index = std::stoi(part.substr(lb + 1, part.size() - lb - 2));
      } catch (const std::exception&) {
        throw InputError("bad index in key '" + o.key + "'", o.where());
      }
      part = part.substr(0, lb);
    }
    if (part.empty()) throw InputError("empty part in key '" + o.key + "'", o.where());
    o.parts.emplace_back(part, index);
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  try {
    o.holder = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    o.holder = toml::table{};
    o.holder.insert("v", value);
  }
  return o;
}

/// Puts the override's value into the scene's table (nothing is validated here).
void edit_table(toml::table& root, Override& o) {
  toml::table* t = &root;
  for (std::size_t i = 0; i + 1 < o.parts.size(); ++i) {
    const auto& [name, index] = o.parts[i];
    toml::node* n = t->get(name);
    if (!n) {
      t->insert(name, toml::table{});
      n = t->get(name);
    }
    if (index >= 0) {
      auto* a = n->as_array();
      if (!a || !a->is_array_of_tables() || index >= static_cast<int>(a->size()))
        throw InputError("no element " + std::to_string(index) + " in '" + name + "'", o.where());
      t = (*a)[static_cast<std::size_t>(index)].as_table();
    } else {
      t = n->as_table();
      if (!t) throw InputError("'" + name + "' is not a table", o.where());
    }
  }
  const std::string& leaf = o.parts.back().first;
  if (o.parts.back().second >= 0)
    throw InputError("cannot replace a whole element; set one of its keys, e.g. '" + o.key + ".value'", o.where());
  if (o.parts.size() == 2 && o.parts[0].first == "mesh") {
    if (leaf == "generator") t->erase("file");
    if (leaf == "file") {
      for (const char* k : {"generator", "n", "seed", "domain"}) t->erase(k);
      if (auto* sv = o.holder.get("v"); sv && sv->is_string()) {
        std::filesystem::path p(sv->as_string()->get());
        if (p.is_relative() && !p.empty()) o.holder.insert_or_assign("v", std::filesystem::absolute(p).lexically_normal().string());
      }
    }
  }
  o.holder.get("v")->visit([&](auto&& v) { t->insert_or_assign(leaf, v); });
}

}  // namespace

void apply_overrides(Scene& scene, const std::vector<std::string>& key_eq_values) {
  if (key_eq_values.empty()) return;
  std::vector<Override> overrides;
  for (const auto& kv : key_eq_values) overrides.push_back(parse_override(kv));
  Scene base = scene;
  for (const auto& o : overrides)
    if (o.parts.front().first == "contact" && !base.contact) base.contact = SceneContact{};
  toml::table root = parse_toml(to_toml(base), "<resolved scene>");
  for (auto& o : overrides) edit_table(root, o);

  Scene updated;
  try {
    updated = scene_from_table(root, "--set", std::filesystem::current_path());
  } catch (const InputError& e) {
    // blame the override whose key the message's key path shares most with (the later one on
    // a tie); "--set" alone when the message names none of them
    const std::string& m = e.detail();
    std::string where = "--set";
    std::size_t best = 0;
    for (const auto& o : overrides) {
      if (m.rfind(o.parts.front().first, 0) != 0) continue;
      std::size_t k = 0;
      while (k < o.key.size() && k < m.size() && o.key[k] == m[k]) ++k;
      if (k >= best) best = k, where = o.where();
    }
    if (best == 0)  // "unknown key 'x' in [...]": the override with that key
      for (const auto& o : overrides)
        for (const auto& part : o.parts)
          if (m.find("'" + part.first + "'") != std::string::npos) where = o.where();
    if (where == "--set" && overrides.size() == 1) where = overrides.front().where();
    throw InputError(m, where);
  }
  updated.source = scene.source;
  updated.lines = scene.lines;
  for (const auto& o : overrides) updated.lines[o.key] = 0;
  scene = std::move(updated);
}

void apply_override(Scene& scene, std::string_view key_eq_value) {
  apply_overrides(scene, {std::string(key_eq_value)});
}

std::vector<std::string> scene_warnings(const Scene& scene) {
  auto zero = [](const SceneScalar& v) { return !v.is_expression() && v.value == 0.0; };
  bool driven = !zero(scene.body_force[0]) || !zero(scene.body_force[1]);
  for (const auto& t : scene.tractions)
    driven = driven || (t.pressure ? !zero(*t.pressure) : !zero(t.value[0]) || !zero(t.value[1]));
  for (const auto& d : scene.dirichlet) driven = driven || (d.ux && !zero(*d.ux)) || (d.uy && !zero(*d.uy));
  if (scene.contact)
    driven = driven || scene.contact->obstacle.has_value() || scene.contact->gap.is_expression() ||
             scene.contact->gap.value < 0.0;
  std::vector<std::string> out;
  if (!driven)
    out.push_back("nothing drives this problem: no load, no prescribed displacement other than zero and no "
                  "obstacle; its solution is u = 0 unless the contact law pushes at u_nu = 0 (a missing [loads] table "
                  "means no loads)");
  return out;
}

std::unique_ptr<BuiltProblem> build_problem(const Scene& scene) {
  auto out = std::make_unique<BuiltProblem>();
  Mesh& mesh = out->mesh;
  if (!scene.mesh.file.empty()) {
    const std::string ext = lower(scene.mesh.file.extension().string());
    if (ext == ".msh") mesh = read_gmsh(scene.mesh.file);
    else if (ext == ".poly2d") mesh = read_poly2d(scene.mesh.file).mesh;
    else throw InputError("mesh.file: unknown mesh format; expected .poly2d or .msh", scene.where("mesh.file"));
    double corners = 0.0;
    for (int e = 0; e < mesh.num_elements(); ++e) corners += static_cast<double>(mesh.element(e).size());
    const MemoryEstimate need =
        estimate_memory(mesh.num_vertices(), mesh.num_elements() ? corners / mesh.num_elements() : 4.0);
    require_memory(need.solve_bytes, scene.mesh.file.string() + ": " + count_text(need.vertices) + " vertices",
                   scene.where("mesh.file"));
  } else {
    const auto& d = scene.mesh.domain;
    const MemoryEstimate need = estimate_memory(scene.mesh.generator, scene.mesh.n);
    require_memory(need.solve_bytes,
                   scene.mesh.generator + " n = " + std::to_string(scene.mesh.n) + ": " + count_text(need.vertices) +
                       " vertices",
                   scene.where("mesh.n"));
    try {
      if (scene.mesh.polygon.empty()) {
        mesh = make_mesh(scene.mesh.generator, scene.mesh.n, Rectangle{d[0], d[1], d[2], d[3]},
                         static_cast<std::uint64_t>(scene.mesh.seed));
      } else {
        PolygonDomain poly;
        for (const auto& p : scene.mesh.polygon) poly.corners.emplace_back(p[0], p[1]);
        mesh = make_mesh(scene.mesh.generator, scene.mesh.n, poly, static_cast<std::uint64_t>(scene.mesh.seed));
      }
    } catch (const MeshError& e) {
      throw MeshError("mesh: the generated mesh is invalid: " + e.detail(), e.element(), scene.where("mesh"));
    } catch (const InputError& e) {
      throw InputError("mesh: " + e.detail(), scene.where("mesh"));
    }
  }

  // Regions given by boxes, then materials by region.
  if (std::any_of(scene.material.regions.begin(), scene.material.regions.end(), [](const auto& r) { return r.box; })) {
    std::vector<int> ids = mesh.regions();
    ids.resize(static_cast<std::size_t>(mesh.num_elements()), 0);
    for (const auto& r : scene.material.regions) {
      if (!r.box) continue;
      const auto& b = *r.box;
      for (int e = 0; e < mesh.num_elements(); ++e) {
        const Vec2 c = mesh.centroid(e);
        if (c.x() >= b[0] && c.x() <= b[1] && c.y() >= b[2] && c.y() <= b[3]) ids[static_cast<std::size_t>(e)] = r.region;
      }
    }
    mesh.set_regions(std::move(ids));
  }
  out->problem = make_contact_problem(scene, mesh);
  out->has_contact = scene.contact.has_value();
  out->warnings = scene_warnings(scene);
  return out;
}

namespace {

ScalarExpression field(const SceneScalar& v) {
  return v.is_expression() ? ScalarExpression::parse(v.expression) : ScalarExpression(v.value);
}

/// A scalar field that refuses a value that is not finite, naming the scene key.
std::function<double(const Vec2&)> finite_scalar(ScalarExpression e, const Scene& scene, const std::string& key) {
  return [e = std::move(e), key, where = scene.where(key)](const Vec2& x) {
    const double value = e(x);
    if (!std::isfinite(value))
      throw InputError(key + " = '" + e.text() + "' gives a value that is not finite at (" + fmt(x.x()) + ", " +
                           fmt(x.y()) + ")",
                       where);
    return value;
  };
}

/// The vector field (ex, ey) that refuses a value that is not finite, naming the scene key.
VectorField finite_vector(ScalarExpression ex, ScalarExpression ey, const Scene& scene,
                          const std::array<std::string, 2>& keys) {
  auto fx = finite_scalar(std::move(ex), scene, keys[0]);
  auto fy = finite_scalar(std::move(ey), scene, keys[1]);
  return [fx, fy](const Vec2& x) { return Vec2(fx(x), fy(x)); };
}

}  // namespace

ContactProblem make_contact_problem(const Scene& scene, const Mesh& mesh) {
  int regions = 1;
  for (int r : mesh.regions()) regions = std::max(regions, r + 1);
  for (const auto& r : scene.material.regions) regions = std::max(regions, r.region + 1);
  std::vector<Material> by_region(static_cast<std::size_t>(regions), Material{scene.material.young, scene.material.poisson});
  for (const auto& r : scene.material.regions) by_region[static_cast<std::size_t>(r.region)] = Material{r.young, r.poisson};
  ContactProblem p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(by_region, scene.material.model);
  p.elasticity.stabilization = scene.material.stabilization;

  const Rectangle box = mesh.bounding_box();
  auto select = [&](const BoundarySelector& b, const std::string& key) {
    std::vector<Segment> segs;
    for (const auto& side : b.sides) segs.push_back(rectangle_side(box, side, b.tolerance));
    for (const auto& s : b.segments) segs.push_back(Segment{Vec2(s[0], s[1]), Vec2(s[2], s[3]), b.tolerance});
    std::vector<int> edges;
    if (!segs.empty()) edges = select_boundary_edges(mesh, segs);
    for (const auto& g : b.groups) {
      try {
        const auto e = select_boundary_edges(mesh, g);
        edges.insert(edges.end(), e.begin(), e.end());
      } catch (const InputError& e) {
        throw InputError(key + ".group: " + e.detail(), scene.where(key + ".group"));
      }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    if (edges.empty()) throw InputError(key + ": selects no boundary edge of the mesh", scene.where(key));
    return edges;
  };

  if (!scene.clamped.empty()) p.elasticity.dirichlet.push_back({select(scene.clamped, "clamped"), {}, {true, true}});
  for (std::size_t i = 0; i < scene.dirichlet.size(); ++i) {
    const auto& d = scene.dirichlet[i];
    const std::string key = "dirichlet[" + std::to_string(i) + "]";
    const ScalarExpression ux = d.ux ? field(*d.ux) : ScalarExpression(0.0);
    const ScalarExpression uy = d.uy ? field(*d.uy) : ScalarExpression(0.0);
    // the keys that gave the components, for messages
    const bool as_value = scene.lines.count(key + ".value") > 0;
    const std::array<std::string, 2> keys{as_value ? key + ".value" : key + ".ux", as_value ? key + ".value" : key + ".uy"};
    p.elasticity.dirichlet.push_back(
        {select(d.boundary, key), finite_vector(ux, uy, scene, keys), {d.ux.has_value(), d.uy.has_value()}});
  }
  const auto& f = scene.body_force;
  if (f[0].is_expression() || f[1].is_expression() || f[0].value != 0.0 || f[1].value != 0.0)
    p.elasticity.body_force = finite_vector(field(f[0]), field(f[1]), scene, {"loads.body_force", "loads.body_force"});
  for (std::size_t i = 0; i < scene.tractions.size(); ++i) {
    const auto& t = scene.tractions[i];
    const std::string key = "loads.traction[" + std::to_string(i) + "]";
    TractionLoad load;
    load.edges = select(t.boundary, key);
    if (t.pressure) load.pressure = finite_scalar(field(*t.pressure), scene, key + ".pressure");
    else load.traction = finite_vector(field(t.value[0]), field(t.value[1]), scene, {key + ".value", key + ".value"});
    p.elasticity.tractions.push_back(std::move(load));
  }
  if (scene.contact) {
    const auto& c = *scene.contact;
    p.contact_edges = select(c.boundary, "contact");
    {  // a part whose every node is clamped leaves nothing to touch: an error, not a silent drop
      std::set<int> fixed, touching;
      for (const auto& d : p.elasticity.dirichlet)
        if (d.fix[0] && d.fix[1])
          for (int e : d.edges) fixed.insert({mesh.edge(e).v0, mesh.edge(e).v1});
      for (int e : p.contact_edges) touching.insert({mesh.edge(e).v0, mesh.edge(e).v1});
      if (std::includes(fixed.begin(), fixed.end(), touching.begin(), touching.end()))
        throw InputError("contact: every node of the contact part is also clamped ([clamped] or a [[dirichlet]] "
                         "with both components), so nothing is left to touch; end one of the parts before the other",
                         scene.where("contact"));
    }
    if (c.obstacle) p.obstacle = make_obstacle(*c.obstacle);
    else p.gap = [g = field(c.gap), where = scene.where("contact.gap")](const Vec2& x) {
      const double value = g(x);
      if (!(std::isfinite(value) && value >= 0.0))
        throw InputError("contact.gap = '" + g.text() + "' gives " + fmt(value) + " at (" + fmt(x.x()) + ", " +
                             fmt(x.y()) + "); a gap must be finite and >= 0",
                         where);
      return value;
    };
    try {
      p.law = make_law(c.law);
    } catch (const InputError& e) {
      throw InputError("contact.law: " + e.detail(), scene.where("contact.law"));
    }
    p.constraint = c.constraint;
  } else {
    p.constraint = ConstraintKind::none;
  }
  return p;
}

}  // namespace hemivem
