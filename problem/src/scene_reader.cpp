#include "scene_reader.hpp"

#include <charconv>
#include <limits>

namespace hemivem {
namespace detail {

std::string lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return r;
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

using detail::lower;

namespace {

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

}  // namespace hemivem
