// Reading a scene's TOML (scene.hpp): the table reader that records every key's line and names
// file, line and key in its errors, and the pieces the scene's schema, writer, overrides and
// builder share. Internal to the library.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/error.hpp>
#include <hemivem/scene/expression.hpp>
#include <hemivem/contact/obstacle.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::detail {

/// `s` in lower case (ASCII).
std::string lower(std::string_view s);
/// "a, b, c".
std::string join(const std::vector<std::string>& v);
/// The shortest text that reads back as `v`, always a TOML float ("1.0", "2e-05").
std::string fmt(double v);
/// "a string", "an integer" ...: the type of a TOML node, for messages.
std::string type_name(const toml::node& n);
/// Parses TOML text; a syntax error is an InputError at "name:line:column".
toml::table parse_toml(std::string_view text, const std::string& name);
/// The folder relative mesh paths of the scene `name` are resolved against.
std::filesystem::path base_folder(const std::string& name);

/// What a scene was read from: the text (parsed again for every apply_overrides, so that its
/// keys keep their lines), the folder relative mesh paths are resolved against, the overrides
/// applied since, in order, and the scene all that gave (to tell whether it was changed since).
struct SceneDocument {
  std::string text;
  std::filesystem::path base;
  std::vector<std::string> overrides;
  Scene scene;  ///< with a null document
};

/// The scene a parsed TOML document describes, validated (the schema: scene_schema.cpp).
/// `source` names the document in messages; relative mesh paths are resolved against `base`.
Scene scene_from_table(const toml::table& root, std::string source, const std::filesystem::path& base);

/// The contact law and the obstacle of a scene (scene_build.cpp); InputError for bad data.
std::shared_ptr<const ContactLaw> make_law(const SceneLaw& law);
/// The friction law of [contact.friction] (tresca, slip-weakening, or an even piecewise law);
/// InputError for parameters out of range or a piecewise law that is not even.
std::shared_ptr<const ContactLaw> make_friction_law(const SceneLaw& law);
/// The friction bound of [contact.friction] when it depends on the normal contact ("coulomb",
/// or "tresca" with a bound table; make_friction_law is then tresca_law(1)); none otherwise.
std::optional<FrictionBound> make_friction_bound(const SceneLaw& law);
Obstacle make_obstacle(const SceneObstacle& o);
/// The obstacle of a three-dimensional scene (plane, sphere, cylinder; scene3d.cpp).
Obstacle3D make_obstacle3d(const SceneObstacle& o);

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
  /// A number, or a string holding an expression in x, y (z in a three-dimensional scene) and t
  /// (parsed here, so that a syntax error names the key's line).
  SceneScalar as_scalar(std::string_view key, const toml::node& n, const std::string& element = "") const {
    const int dimension = scene_.mesh.dimension;
    if (const auto* text = n.as_string()) {
      try {
        (void)ScalarExpression::parse(text->get(), dimension);
      } catch (const InputError& e) {
        fail(key, n, element + e.detail());
      }
      return SceneScalar{0.0, text->get()};
    }
    if (!n.is_integer() && !n.is_floating_point())
      fail(key, n, element + (dimension == 3 ? "expected a number or an expression in x, y and z (a string), got "
                                             : "expected a number or an expression in x and y (a string), got ") +
                       type_name(n));
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

}  // namespace hemivem::detail
