# The engines of hemivem: the one list that the factories, FactorizationOptions::is_valid,
# the command's help, the build and the package config read.
#
# One row per engine: name (as on the command line) | class | header | packages a static
# build of it links privately. Its folder is backends/<kind>/<name>, its target
# hemivem_<kind>_<name with '-' as '_'>.
#
# hemivem_write_engine_names(<file>) writes hemivem/engine_names.hpp: every known name, built
# or not. hemivem_write_engine_registry(<kind> <file> <name>...) writes the registry of the
# engines named, for the factory of that kind (see backends/*/factory.cpp):
#
#   #include <hemivem/ssn_minimizer.hpp>          one line per built engine
#   ...
#   #define HEMIVEM_ENGINES(X) X("ssn", SsnMinimizer) X("bundle-dca", BundleDcaMinimizer) ...

set(HEMIVEM_LINEAR_ENGINE_TABLE
  "eigen|EigenFactorization|hemivem/eigen_factorization.hpp|"
  "cholmod|CholmodFactorization|hemivem/cholmod_factorization.hpp|CHOLMOD"
  "mumps|MumpsFactorization|hemivem/mumps_factorization.hpp|MUMPS_seq"
  "mumps-mpi|MumpsMpiFactorization|hemivem/mumps_mpi_factorization.hpp|MUMPS_mpi")
set(HEMIVEM_NONSMOOTH_ENGINE_TABLE
  "ssn|SsnMinimizer|hemivem/ssn_minimizer.hpp|"
  "bundle-dca|BundleDcaMinimizer|hemivem/bundle_dca_minimizer.hpp|"
  "nlopt-mma|NloptMmaMinimizer|hemivem/nlopt_mma_minimizer.hpp|NLopt"
  "ceres-active-set|CeresActiveSetMinimizer|hemivem/ceres_active_set_minimizer.hpp|Ceres")

# The names of one kind (linear | nonsmooth), in the table's order.
function(hemivem_engine_names kind out)
  string(TOUPPER ${kind} KIND)
  set(names)
  foreach(row IN LISTS HEMIVEM_${KIND}_ENGINE_TABLE)
    string(REPLACE "|" ";" row "${row};")
    list(GET row 0 name)
    list(APPEND names ${name})
  endforeach()
  set(${out} ${names} PARENT_SCOPE)
endfunction()

# One field of an engine's row: TARGET (hemivem_<kind>_<name>), CLASS, HEADER or DEPENDENCIES.
function(hemivem_engine_field kind name field out)
  string(TOUPPER ${kind} KIND)
  foreach(row IN LISTS HEMIVEM_${KIND}_ENGINE_TABLE)
    string(REPLACE "|" ";" row "${row};")
    list(GET row 0 row_name)
    if(row_name STREQUAL name)
      string(REPLACE "-" "_" suffix "${name}")
      list(GET row 1 CLASS)
      list(GET row 2 HEADER)
      list(GET row 3 DEPENDENCIES)
      string(REPLACE " " ";" DEPENDENCIES "${DEPENDENCIES}")
      set(TARGET hemivem_${kind}_${suffix})
      set(${out} "${${field}}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  message(FATAL_ERROR "no ${kind} engine '${name}' in cmake/HemivemEngines.cmake")
endfunction()

function(hemivem_write_engine_names file)
  set(body)
  foreach(kind linear nonsmooth)
    hemivem_engine_names(${kind} names)
    list(LENGTH names count)
    list(JOIN names "\", \"" quoted)
    set(function_name known_linear_engines)
    set(what "linear engines (FactorizationOptions::engine)")
    if(kind STREQUAL "nonsmooth")
      set(function_name known_minimizers)
      set(what "nonsmooth minimizers")
    endif()
    string(APPEND body
      "/// The ${what} hemivem knows, built or not.\n"
      "inline constexpr std::array<std::string_view, ${count}> ${function_name}() {\n"
      "  return {\"${quoted}\"};\n"
      "}\n\n")
  endforeach()
  file(CONFIGURE OUTPUT "${file}" @ONLY CONTENT
"// The names of hemivem's engines, generated from cmake/HemivemEngines.cmake (do not edit).
#pragma once

#include <algorithm>
#include <array>
#include <cctype>
#include <string>
#include <string_view>

namespace hemivem {

@body@/// An engine name as the factories compare it: lower case, '_' read as '-'.
inline std::string normalized_engine_name(std::string_view name) {
  std::string out(name);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) {
    return c == '_' ? '-' : static_cast<char>(std::tolower(c));
  });
  return out;
}

/// True when `names` (one of the lists above) holds the normalized `name`.
template <class Names>
bool is_known_engine(const Names& names, std::string_view name) {
  const std::string n = normalized_engine_name(name);
  return std::find(names.begin(), names.end(), n) != names.end();
}

/// `names` joined by `separator`.
template <class Names>
std::string join_engine_names(const Names& names, std::string_view separator = \", \") {
  std::string out;
  for (const auto& name : names) {
    if (!out.empty()) out += separator;
    out += name;
  }
  return out;
}

}  // namespace hemivem
")
endfunction()

# The registry of the engines `names` (of one kind) for that kind's factory.
function(hemivem_write_engine_registry kind file)
  set(includes)
  set(entries)
  foreach(name IN LISTS ARGN)
    hemivem_engine_field(${kind} ${name} HEADER header)
    hemivem_engine_field(${kind} ${name} CLASS class)
    string(APPEND includes "#include <${header}>\n")
    string(APPEND entries " X(\"${name}\", ${class})")
  endforeach()
  file(CONFIGURE OUTPUT "${file}" @ONLY CONTENT
"// The ${kind} engines linked into this build, generated from cmake/HemivemEngines.cmake
// (do not edit).
#pragma once

@includes@
#define HEMIVEM_ENGINES(X)@entries@
")
endfunction()
