// --set: "dotted.key=value" overrides of a scene.
#include <hemivem/scene/scene.hpp>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <optional>
#include <sstream>

#include "scene_reader.hpp"

namespace hemivem {

using detail::parse_toml;
using detail::scene_from_table;

namespace {

/// The index of "name[+]" in Override::parts: append a table to the array of tables.
constexpr int kAppend = -2;

/// One "dotted.key=value" override: the key, its path ("name[i]" selects element i of an
/// array of tables, "name[+]" appends one) and the value in TOML syntax (a bare word is a string).
struct Override {
  std::string key;
  std::vector<std::pair<std::string, int>> parts;
  toml::table holder;  ///< the value as "v"
  bool remove = false; ///< "key=" (nothing after '='): the key is removed
  std::string text;    ///< "key=value" as given; a relative mesh.file made absolute by edit_table
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
  o.text = std::string(key_eq_value);
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
      const std::string inside = part.substr(lb + 1, part.size() - lb - 2);
      if (inside == "+") {
        if (dot != std::string::npos)
          throw InputError("'[+]' appends a whole table and ends the key, e.g. 'dirichlet[+]={side=\"left\", ux=0}'",
                           o.where());
        index = kAppend;
      } else {
        std::size_t used = 0;
        try {
          index = std::stoi(inside, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == 0 || used != inside.size() || index < 0)
          throw InputError("bad index in key '" + o.key + "' (an index from 0, or '+' to append)", o.where());
      }
      part = part.substr(0, lb);
    }
    if (part.empty()) throw InputError("empty part in key '" + o.key + "'", o.where());
    o.parts.emplace_back(part, index);
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (value.empty()) {
    o.remove = true;
    return o;
  }
  try {
    o.holder = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    char* end = nullptr;
    errno = 0;
    const double number = std::strtod(value.c_str(), &end);
    if (end == value.c_str() + value.size() && errno == ERANGE && number != 0.0)
      throw InputError(value + " is out of the range of a number (the largest finite one is about 1.8e308)", o.where());
    o.holder = toml::table{};
    o.holder.insert("v", value);
  }
  return o;
}

/// How many tables `node` holds as an array of tables: its size, 1 for a single table (a
/// [contact] that "contact=[...]" replaces), none for anything else.
std::optional<std::size_t> tables_in(const toml::node* node) {
  if (!node) return std::nullopt;
  if (node->is_table()) return 1;
  const auto* a = node->as_array();
  if (a && !a->empty() && a->is_array_of_tables()) return a->size();
  return std::nullopt;
}

/// "key[+]={...}": appends the value, a table, to the array of tables `leaf` of `t` (made when
/// missing; a single table becomes the first of two).
void append_table(toml::table& t, const std::string& leaf, const Override& o) {
  const auto* value = o.holder.get("v") ? o.holder.get("v")->as_table() : nullptr;
  if (!value)
    throw InputError("'[+]' appends one table: give it as {key = value, ...}, e.g. 'dirichlet[+]={side=\"left\", ux=0}'",
                     o.where());
  toml::node* n = t.get(leaf);
  if (!n) {
    t.insert(leaf, toml::array{*value});
  } else if (auto* a = n->as_array(); a && (a->empty() || a->is_array_of_tables())) {
    a->push_back(*value);
  } else if (const auto* single = n->as_table()) {
    toml::array both{*single, *value};
    t.insert_or_assign(leaf, std::move(both));
  } else {
    throw InputError("'" + leaf + "' is not an array of tables: nothing to append to", o.where());
  }
}

/// What replacing (or removing) the key `leaf` of `t` by the override drops, as a sentence, when
/// the key holds tables and the new value is not the single table it replaces; "" otherwise.
std::string replacement_notice(const toml::table& t, const std::string& leaf, const Override& o) {
  const toml::node* old = t.get(leaf);
  const std::optional<std::size_t> before = tables_in(old);
  if (!before) return "";
  const toml::node* value = o.remove ? nullptr : o.holder.get("v");
  if (old->is_table() && (o.remove || !value->is_array())) return "";  // a table set or removed as such
  const std::string count = *before == 1 ? "its 1 table" : "its " + std::to_string(*before) + " tables";
  if (o.remove) return o.where() + " removed [[" + o.key + "]] with " + count;
  const std::size_t after = value->is_array() ? value->as_array()->size() : 1;
  return o.where() + " replaced the whole array [[" + o.key + "]]: " + count + " by " + std::to_string(after) +
         " (to add one table instead: --set '" + o.key + "[+]={...}')";
}

/// Puts the override's value into the scene's table (nothing is validated here); returns what
/// it dropped beyond the key (replacement_notice), "" when nothing.
std::string edit_table(toml::table& root, Override& o) {
  toml::table* t = &root;
  for (std::size_t i = 0; i + 1 < o.parts.size(); ++i) {
    const auto& [name, index] = o.parts[i];
    toml::node* n = t->get(name);
    if (!n) {
      t->insert(name, toml::table{});
      n = t->get(name);
    }
    auto* a = n->as_array();
    if (index == 0 && n->is_table()) {  // "contact[0]": the single [contact] table
      t = n->as_table();
    } else if (index >= 0) {
      if (!a || !a->is_array_of_tables() || index >= static_cast<int>(a->size()))
        throw InputError("no element " + std::to_string(index) + " in '" + name + "' (" +
                             std::to_string(a && a->is_array_of_tables() ? a->size() : n->is_table() ? 1 : 0) +
                             " table(s)); '" + name + "[+]={...}' appends one",
                         o.where());
      t = (*a)[static_cast<std::size_t>(index)].as_table();
    } else if (a && a->is_array_of_tables()) {  // "contact.gap": the only table of [[contact]]
      if (a->size() != 1) {
        std::string example;
        for (std::size_t j = 0; j < o.parts.size(); ++j) {
          example += (j == 0 ? "" : ".") + o.parts[j].first;
          if (j == i) example += "[1]";
          else if (o.parts[j].second >= 0) example.append("[").append(std::to_string(o.parts[j].second)).append("]");
        }
        throw InputError("'" + name + "' has " + std::to_string(a->size()) + " tables ([[" + name +
                             "]]); name one by its index, e.g. '" + example + "'",
                         o.where());
      }
      t = (*a)[0].as_table();
    } else {
      t = n->as_table();
      if (!t) throw InputError("'" + name + "' is not a table", o.where());
    }
  }
  const std::string& leaf = o.parts.back().first;
  if (o.parts.back().second == kAppend) {
    if (o.remove) throw InputError("'[+]' appends a table: give one, e.g. '" + o.key + "={...}'", o.where());
    append_table(*t, leaf, o);
    return "";
  }
  if (o.parts.back().second >= 0)
    throw InputError("cannot replace a whole element; set one of its keys, e.g. '" + o.key + ".value'", o.where());
  std::string notice = replacement_notice(*t, leaf, o);
  if (o.remove) {
    if (!t->erase(leaf)) throw InputError("the scene has no key '" + o.key + "' to remove", o.where());
    return notice;
  }
  if (o.parts.size() == 2 && o.parts[0].first == "path") {  // the load factors one way or the other
    if (leaf == "t") t->erase("steps");
    if (leaf == "steps") t->erase("t");
  }
  if (o.parts.size() >= 2 && o.parts[o.parts.size() - 2].first == "mesh") {  // the scene's or a body's mesh
    if (leaf == "generator") t->erase("file");
    if (leaf == "file") {
      for (const char* k : {"generator", "n", "seed", "domain", "center", "radii", "angles", "grading", "focus"}) t->erase(k);
      if (auto* sv = o.holder.get("v"); sv && sv->is_string()) {
        std::filesystem::path p(sv->as_string()->get());
        if (p.is_relative() && !p.empty()) {
          const toml::value<std::string> absolute(std::filesystem::absolute(p).lexically_normal().string());
          std::ostringstream value;
          value << absolute;
          o.holder.insert_or_assign("v", absolute);
          o.text = o.key + "=" + value.str();
        }
      }
    }
  }
  o.holder.get("v")->visit([&](auto&& v) { t->insert_or_assign(leaf, v); });
  return notice;
}

/// A message blamed on "--set key" without the key (or the table holding it) it starts with
/// ("key: ..."): `where` names it.
std::string without_key(const std::string& message, const std::string& where) {
  if (where.rfind("--set ", 0) != 0) return message;
  const std::string key = where.substr(6);
  const auto colon = message.find(": ");
  if (colon == std::string::npos) return message;
  const std::string head = message.substr(0, colon);
  const bool within = key.rfind(head, 0) == 0 && (key.size() == head.size() || key[head.size()] == '.');
  return within ? message.substr(colon + 2) : message;
}

/// A mesh file and a generator's keys given together are refused as the scene reader refuses
/// them: the overrides would contradict each other.
void refuse_contradictions(const std::vector<Override>& overrides) {
  const Override* file = nullptr;
  for (const auto& o : overrides)
    if (o.key == "mesh.file" && !o.remove) file = &o;
  if (file)
    for (const auto& o : overrides)
      for (const char* k : {"generator", "n", "seed", "domain", "center", "radii", "angles", "grading", "focus"})
        if (!o.remove && o.key == std::string("mesh.") + k)
          throw InputError("not used with mesh.file (" + file->where() +
                               "); give either a generator or a file",
                           o.where());
}

}  // namespace

void apply_overrides(Scene& scene, const std::vector<std::string>& key_eq_values) {
  if (key_eq_values.empty()) return;
  std::vector<Override> overrides;
  for (const auto& kv : key_eq_values) overrides.push_back(parse_override(kv));
  refuse_contradictions(overrides);
  // the text the scene was read from with the overrides applied since, unless the scene was
  // made or changed in code: then the scene as written by to_toml
  const detail::SceneDocument* doc = scene.document && scene.document->scene == scene ? scene.document.get() : nullptr;
  const bool read = doc != nullptr;
  const std::string source = read ? scene.source : std::string("--set");
  toml::table root = parse_toml(read ? doc->text : to_toml(scene), read ? source : "<resolved scene>");
  const std::filesystem::path base = read ? doc->base : std::filesystem::current_path();
  std::vector<Override> earlier;
  if (read)
    for (const auto& kv : doc->overrides) earlier.push_back(parse_override(kv));
  std::vector<std::string> notices;
  for (std::vector<Override>* list : {&earlier, &overrides})
    for (auto& o : *list) {
      const bool whole = o.parts.size() == 1;  // "contact=[...]", "contact[+]={...}": no default part first
      if (o.parts.front().first == "contact" && !o.remove && !whole && !root.contains("contact"))  // the default part
        root.insert("contact", toml::table{{"side", toml::array{"bottom"}}});
      std::string notice = edit_table(root, o);
      if (list == &overrides && !notice.empty()) notices.push_back(std::move(notice));
    }

  Scene updated;
  try {
    updated = scene_from_table(root, source, base);
  } catch (const InputError& e) {
    const std::string& m = e.detail();
    if (read && e.where() != source) {  // at a line of the file: blame an override only when its key is the
      const std::string key = m.substr(0, m.find(": "));  // message's key, inside it or around it
      auto within = [](const std::string& inner, const std::string& outer) {
        return inner.rfind(outer, 0) == 0 && (inner.size() == outer.size() || inner[outer.size()] == '.');
      };
      const Override* blamed = nullptr;
      for (const auto& o : overrides)
        if (within(o.key, key) || within(key, o.key)) blamed = &o;
      if (!blamed) throw;
      throw InputError(without_key(m, blamed->where()), blamed->where());
    }
    // else blame the override whose key the message's key path shares most with (the later
    // one on a tie); "--set" alone when the message names none of them
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
    throw InputError(without_key(m, where), where);
  }
  updated.source = scene.source;
  updated.override_notices = scene.override_notices;
  updated.override_notices.insert(updated.override_notices.end(), notices.begin(), notices.end());
  if (!read) updated.lines = scene.lines;
  for (const auto* list : {&earlier, &overrides})
    for (const auto& o : *list) updated.lines[o.key] = 0;
  if (read) {  // lines of a scene written by to_toml would not be the file's
    detail::SceneDocument next{doc->text, base, doc->overrides, updated};
    for (const auto& o : overrides) next.overrides.push_back(o.text);
    updated.document = std::make_shared<const detail::SceneDocument>(std::move(next));
  }
  scene = std::move(updated);
}

void apply_override(Scene& scene, std::string_view key_eq_value) {
  apply_overrides(scene, {std::string(key_eq_value)});
}

}  // namespace hemivem
