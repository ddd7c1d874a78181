#include "scene_reader.hpp"

#include <charconv>
#include <limits>

namespace hemivem {
namespace detail {

std::string lower(std::string_view s) { return to_lower(s); }

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
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time:
      return "a date/time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

std::string fmt(double v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, end);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // keep it a TOML float
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

}  // namespace detail

}  // namespace hemivem
