# The engines of hemivem. Each engine folder (backends/<kind>/<name>/CMakeLists.txt) declares
# its engine with one call:
#
#   hemivem_add_engine(KIND linear NAME cholmod CLASS CholmodFactorization
#                      HEADER hemivem/cholmod_factorization.hpp
#                      SOURCES src/cholmod_factorization.cpp
#                      IF CHOLMOD_FOUND
#                      DEPENDS CHOLMOD::CHOLMOD PACKAGES CHOLMOD HELPERS hemivem_linear_common)
#
#   KIND      linear (a SparseFactorization), nonsmooth (a NonsmoothMinimizer) or krylov (a
#             KrylovSolver, hemivem/krylov_solver.hpp)
#   NAME      its name on the command line, in scenes and as a package component
#   CLASS     the class the factory creates, declared in HEADER, with a constructor taking
#             FactorizationOptions (linear), the class' Options (nonsmooth) or nothing (krylov)
#   SOURCES   its sources; its public headers are the folder's include/hemivem/*.hpp
#   IF        a condition (the words of an if()) under which it is built; default: always
#   DEPENDS   targets it links privately: its package
#   PACKAGES  those packages as the package config finds them for a static build (CHOLMOD,
#             MUMPS_seq, MUMPS_mpi, or a package with a CMake config: NLopt, Ceres)
#   HELPERS   private header-only targets of this build tree (not installed) it uses
#   PROPERTIES  more properties of its target (set_target_properties)
#   LOADED_AT_RUN_TIME  the factory does not link it: it loads a module at run time instead
#             (mumps-mpi, see backends/linear/factory.cpp)
#   MODULE_ONLY  with LOADED_AT_RUN_TIME: no linkable library either, the folder builds the
#             module alone (petsc-gamg and petsc-hypre, whose PETSc links the MPI build of MUMPS:
#             backends/krylov/petsc); BUILT still says whether the condition holds
#
# Every engine declared is known, built or not; the names of a kind are in the order of the
# calls, that is the order in which backends/<kind>/CMakeLists.txt adds the folders. When its
# condition holds the engine is the library hemivem_<kind>_<name with '-' as '_'>, also
# hemivem::<kind>_<name with '-' as '_'>, exported under that name (cmake/HemivemPackage.cmake);
# a MODULE_ONLY engine has no such library.
#
# What the rest of the build reads from the calls:
#   hemivem_engines(<kind> <out> [BUILT] [LINKED])   the names declared, built, or built and
#       linked by the factory, in order
#   hemivem_engine_property(<kind> <name> <CLASS|HEADER|TARGET|PACKAGES|BUILT|LINKED> <out>)
#   hemivem_write_engine_names(<file>)   hemivem/engine_names.hpp: every name known, for
#       FactorizationOptions::is_valid, the command's help and the scene schema
#   hemivem_write_engine_registry(<kind> <file>)   the factory's registry: the header of every
#       engine it links, HEMIVEM_ENGINES(X) calling X("name", Class) for each, and
#       HEMIVEM_ENGINE_<NAME> (upper case, '-' as '_') defined as 1 for each
#       (backends/<kind>/factory.cpp)
#   The names of every kind are in hemivem/engine_names.hpp: known_linear_engines(),
#   known_minimizers(), known_krylov_engines().

# Generated public headers (hemivem/engine_names.hpp), on hemivem::interfaces' include path.
set(HEMIVEM_GENERATED_INCLUDE_DIR ${PROJECT_BINARY_DIR}/generated/include)

function(hemivem_add_engine)
  cmake_parse_arguments(PARSE_ARGV 0 ARG "LOADED_AT_RUN_TIME;MODULE_ONLY" "KIND;NAME;CLASS;HEADER"
                        "SOURCES;IF;DEPENDS;PACKAGES;HELPERS;PROPERTIES")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "hemivem_add_engine: unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  foreach(required KIND NAME CLASS HEADER SOURCES)
    if(NOT ARG_${required})
      message(FATAL_ERROR "hemivem_add_engine(${ARG_NAME}): ${required} is missing")
    endif()
  endforeach()
  if(NOT ARG_KIND MATCHES "^(linear|nonsmooth|krylov)$")
    message(FATAL_ERROR "hemivem_add_engine(${ARG_NAME}): KIND is linear, nonsmooth or krylov, not '${ARG_KIND}'")
  endif()
  if(ARG_MODULE_ONLY AND NOT ARG_LOADED_AT_RUN_TIME)
    message(FATAL_ERROR "hemivem_add_engine(${ARG_NAME}): MODULE_ONLY needs LOADED_AT_RUN_TIME")
  endif()
  hemivem_engines(${ARG_KIND} known)
  if(ARG_NAME IN_LIST known)
    message(FATAL_ERROR "hemivem_add_engine: the ${ARG_KIND} engine '${ARG_NAME}' is declared twice")
  endif()

  string(REPLACE "-" "_" suffix "${ARG_NAME}")
  set(target hemivem_${ARG_KIND}_${suffix})
  set(built TRUE)
  if(DEFINED ARG_IF AND NOT (${ARG_IF}))
    set(built FALSE)
  endif()
  set(linked ${built})
  if(ARG_LOADED_AT_RUN_TIME)
    set(linked FALSE)
  endif()

  set_property(GLOBAL APPEND PROPERTY HEMIVEM_${ARG_KIND}_ENGINES ${ARG_NAME})
  set(prefix HEMIVEM_ENGINE_${ARG_KIND}_${ARG_NAME})
  set_property(GLOBAL PROPERTY ${prefix}_CLASS ${ARG_CLASS})
  set_property(GLOBAL PROPERTY ${prefix}_HEADER ${ARG_HEADER})
  set_property(GLOBAL PROPERTY ${prefix}_TARGET ${target})
  set_property(GLOBAL PROPERTY ${prefix}_PACKAGES ${ARG_PACKAGES})
  set_property(GLOBAL PROPERTY ${prefix}_BUILT ${built})
  set_property(GLOBAL PROPERTY ${prefix}_LINKED ${linked})
  if(NOT built OR ARG_MODULE_ONLY)
    return()
  endif()

  add_library(${target} ${ARG_SOURCES})
  add_library(hemivem::${ARG_KIND}_${suffix} ALIAS ${target})
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON ${ARG_PROPERTIES})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(${target} PUBLIC hemivem::interfaces PRIVATE ${ARG_DEPENDS})
  foreach(helper IN LISTS ARG_HELPERS)
    target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:${helper}>)
  endforeach()
  target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic>)
endfunction()

function(hemivem_engines kind out)
  cmake_parse_arguments(PARSE_ARGV 2 ARG "BUILT;LINKED" "" "")
  get_property(names GLOBAL PROPERTY HEMIVEM_${kind}_ENGINES)
  set(selected)
  foreach(name IN LISTS names)
    get_property(built GLOBAL PROPERTY HEMIVEM_ENGINE_${kind}_${name}_BUILT)
    get_property(linked GLOBAL PROPERTY HEMIVEM_ENGINE_${kind}_${name}_LINKED)
    if((ARG_BUILT AND NOT built) OR (ARG_LINKED AND NOT linked))
      continue()
    endif()
    list(APPEND selected ${name})
  endforeach()
  set(${out} ${selected} PARENT_SCOPE)
endfunction()

function(hemivem_engine_property kind name field out)
  get_property(declared GLOBAL PROPERTY HEMIVEM_ENGINE_${kind}_${name}_CLASS SET)
  if(NOT declared OR NOT field MATCHES "^(CLASS|HEADER|TARGET|PACKAGES|BUILT|LINKED)$")
    message(FATAL_ERROR "hemivem_engine_property: no ${kind} engine '${name}' or no property ${field}")
  endif()
  get_property(value GLOBAL PROPERTY HEMIVEM_ENGINE_${kind}_${name}_${field})
  set(${out} "${value}" PARENT_SCOPE)
endfunction()

function(hemivem_write_engine_names file)
  set(body)
  foreach(kind linear nonsmooth krylov)
    hemivem_engines(${kind} names)
    list(LENGTH names count)
    list(JOIN names "\", \"" quoted)
    set(function_name known_linear_engines)
    set(what "linear engines (FactorizationOptions::engine)")
    if(kind STREQUAL "nonsmooth")
      set(function_name known_minimizers)
      set(what "nonsmooth minimizers")
    elseif(kind STREQUAL "krylov")
      set(function_name known_krylov_engines)
      set(what "Krylov solvers (make_krylov_solver, in order of preference)")
    endif()
    set(list "{\"${quoted}\"}")
    if(count EQUAL 0)
      set(list "{}")
    endif()
    string(APPEND body
      "/// The ${what} hemivem knows, built or not.\n"
      "inline constexpr std::array<std::string_view, ${count}> ${function_name}() {\n"
      "  return ${list};\n"
      "}\n\n")
  endforeach()
  file(CONFIGURE OUTPUT "${file}" @ONLY CONTENT
"// The names of hemivem's engines, generated from the engine folders' hemivem_add_engine()
// calls (cmake/HemivemEngines.cmake; do not edit).
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

function(hemivem_write_engine_registry kind file)
  set(includes)
  set(defines)
  set(entries)
  hemivem_engines(${kind} names LINKED)
  foreach(name IN LISTS names)
    hemivem_engine_property(${kind} ${name} HEADER header)
    hemivem_engine_property(${kind} ${name} CLASS class)
    string(TOUPPER "${name}" macro)
    string(REPLACE "-" "_" macro "${macro}")
    string(APPEND includes "#include <${header}>\n")
    string(APPEND defines "#define HEMIVEM_ENGINE_${macro} 1\n")
    string(APPEND entries " X(\"${name}\", ${class})")
  endforeach()
  file(CONFIGURE OUTPUT "${file}" @ONLY CONTENT
"// The ${kind} engines the factory links in this build, generated from the engine folders'
// hemivem_add_engine() calls (cmake/HemivemEngines.cmake; do not edit).
#pragma once

@includes@
@defines@
#define HEMIVEM_ENGINES(X)@entries@
")
endfunction()

# The factory of one kind of engine: the library hemivem_<kind> (also hemivem::<kind>) built
# from SOURCES, with the folder's include/ as its public headers when there is one, linking
# every engine of the kind that is built and linked (publicly: an engine's header may be used
# directly), with their registry (hemivem_write_engine_registry) on its private include path.
# ENGINES names the variable that receives those engines' names, in order.
function(hemivem_add_engine_factory kind)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "ENGINES" "SOURCES")
  set(target hemivem_${kind})
  add_library(${target} ${ARG_SOURCES})
  add_library(hemivem::${kind} ALIAS ${target})
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_include_directories(${target} PUBLIC
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:include>)
  endif()
  target_link_libraries(${target} PUBLIC hemivem::interfaces)
  target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic>)
  hemivem_engines(${kind} engines LINKED)
  foreach(engine IN LISTS engines)
    hemivem_engine_property(${kind} ${engine} TARGET engine_target)
    target_link_libraries(${target} PUBLIC ${engine_target})
  endforeach()
  hemivem_write_engine_registry(${kind} ${CMAKE_CURRENT_BINARY_DIR}/generated/${kind}_registry.hpp)
  target_include_directories(${target} PRIVATE ${CMAKE_CURRENT_BINARY_DIR}/generated)
  set(${ARG_ENGINES} ${engines} PARENT_SCOPE)
endfunction()
