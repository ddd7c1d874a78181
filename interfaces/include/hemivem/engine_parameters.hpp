// Typed engine options and their adapter from named numbers (the command line's and the
// scene's `[solver.parameters]`).
//
// An engine's options are a plain struct with defaults (as Ceres' Solver::Options), a
// `bool is_valid(std::string* error) const` that names the offending field, and a
// `template <class Visit> void fields(Visit&& visit)` that calls visit(name, member) for every
// member that may be set by name (members of type double, int or bool). From those,
// options_from_parameters() builds the options out of a map name -> number with checked
// conversions: an int field takes only an integer within int's range, a bool field only 0 or 1;
// an unknown name is an error listing the known ones.
#pragma once

#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <hemivem/error.hpp>

namespace hemivem {

/// One settable field of an engine's options, as text: name and current value.
struct ParameterValue {
  std::string name;
  double value = 0.0;
};

namespace detail {

/// The shortest text that reads back as v.
inline std::string show_number(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

template <class T>
void assign_checked(T& member, double v, const std::string& name, const std::string& engine) {
  if constexpr (std::is_same_v<T, double>) {
    if (std::isnan(v)) throw InputError("parameter '" + name + "' is not a number", engine);
    member = v;
  } else if constexpr (std::is_same_v<T, bool>) {
    if (v != 0.0 && v != 1.0)
      throw InputError("parameter '" + name + "' = " + show_number(v) + " must be 0 or 1", engine);
    member = v == 1.0;
  } else {
    static_assert(std::is_same_v<T, int>, "engine options hold double, int or bool fields");
    if (!(v == std::trunc(v)) || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      throw InputError("parameter '" + name + "' = " + show_number(v) + " must be an integer in [" +
                           std::to_string(std::numeric_limits<int>::min()) + ", " +
                           std::to_string(std::numeric_limits<int>::max()) + "]",
                       engine);
    member = static_cast<int>(v);
  }
}

}  // namespace detail

/// The fields of `options` that may be set by name, with their values.
template <class Options>
std::vector<ParameterValue> parameter_values(Options options) {
  std::vector<ParameterValue> out;
  options.fields([&](std::string_view name, auto& member) {
    out.push_back({std::string(name), static_cast<double>(member)});
  });
  return out;
}

/// Options built from the defaults and `values` (name -> number); InputError naming `engine`
/// and the field for an unknown name, a value of the wrong kind, or options that are not valid.
template <class Options>
Options options_from_parameters(const std::map<std::string, double>& values, const std::string& engine) {
  Options options;
  for (const auto& entry : values) {  // not [name, v]: clang captures structured bindings from 16 on
    const std::string& name = entry.first;
    const double v = entry.second;
    bool found = false;
    options.fields([&](std::string_view field, auto& member) {
      if (field != name) return;
      found = true;
      detail::assign_checked(member, v, name, engine);
    });
    if (!found) {
      std::string known;
      for (const auto& p : parameter_values(Options{})) known += (known.empty() ? "" : ", ") + p.name;
      throw InputError("unknown parameter '" + name + "'; " + engine + " knows " + (known.empty() ? "none" : known),
                       engine);
    }
  }
  if (std::string error; !options.is_valid(&error)) throw InputError(error, engine);
  return options;
}

/// Throws InputError naming `engine` unless options.is_valid().
template <class Options>
void require_valid(const Options& options, const std::string& engine) {
  if (std::string error; !options.is_valid(&error)) throw InputError(error, engine);
}

/// The helper of is_valid(): returns false with *error = "name: requirement, got value".
inline bool invalid_field(std::string* error, std::string_view name, std::string_view requirement, double value) {
  if (error) *error = std::string(name) + ": must be " + std::string(requirement) + ", got " + detail::show_number(value);
  return false;
}

}  // namespace hemivem
