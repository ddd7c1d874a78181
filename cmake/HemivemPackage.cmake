# Installation and the package config (included last by the top-level CMakeLists.txt).
#
#   find_package(hemivem CONFIG REQUIRED COMPONENTS cholmod ssn)
#
# gives hemivem::core (always) and one target per component that was built. A component is
# named as the engine on the command line; the factories are the components linear and
# krylov and nonsmooth; the application library (scene -> solve -> result.json) is the component app.
include(CMakePackageConfigHelpers)

set(HEMIVEM_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/hemivem" CACHE STRING
    "Folder (relative to the prefix) of the installed package config")
mark_as_advanced(HEMIVEM_INSTALL_CMAKEDIR)

# component | target (hemivem::<target>) | packages a static build of it links privately;
# one component per engine declared with hemivem_add_engine() (cmake/HemivemEngines.cmake), in
# between.
set(_hemivem_component_table "core|core|CGAL tomlplusplus muparser")
foreach(_kind linear nonsmooth krylov)
  hemivem_engines(${_kind} _names)
  foreach(_name IN LISTS _names)
    hemivem_engine_property(${_kind} ${_name} TARGET _target)
    hemivem_engine_property(${_kind} ${_name} PACKAGES _deps)
    string(REGEX REPLACE "^hemivem_" "" _target ${_target})
    string(REPLACE ";" " " _deps "${_deps}")
    list(APPEND _hemivem_component_table "${_name}|${_target}|${_deps}")
  endforeach()
endforeach()
list(APPEND _hemivem_component_table "linear|linear|" "krylov|krylov|" "nonsmooth|nonsmooth|" "global-search|global_search|" "app|app|ZLIB")

set(HEMIVEM_KNOWN_COMPONENTS)
set(HEMIVEM_BUILT_COMPONENTS)
set(HEMIVEM_STATIC_DEPENDENCIES)
set(_hemivem_exported hemivem_interfaces)
foreach(_row IN LISTS _hemivem_component_table)
  string(REPLACE "|" ";" _row "${_row};")
  list(GET _row 0 _component)
  list(GET _row 1 _target)
  list(GET _row 2 _deps)
  list(APPEND HEMIVEM_KNOWN_COMPONENTS ${_component})
  if(NOT TARGET hemivem_${_target})
    continue()
  endif()
  list(APPEND HEMIVEM_BUILT_COMPONENTS ${_component})
  list(APPEND _hemivem_exported hemivem_${_target})
  string(REPLACE " " ";" _deps "${_deps}")
  list(APPEND HEMIVEM_STATIC_DEPENDENCIES ${_deps})
endforeach()
list(REMOVE_DUPLICATES HEMIVEM_STATIC_DEPENDENCIES)

# Every exported library: hemivem::<name without the hemivem_ prefix>, a version and soname,
# its headers (the include/ folder beside its CMakeLists.txt, or the folders of its property
# HEMIVEM_HEADER_DIRS: hemivem::core has one per module) installed once.
foreach(_target IN LISTS _hemivem_exported)
  string(REGEX REPLACE "^hemivem_" "" _export_name ${_target})
  set_target_properties(${_target} PROPERTIES EXPORT_NAME ${_export_name})
  get_target_property(_type ${_target} TYPE)
  if(NOT _type STREQUAL "INTERFACE_LIBRARY")
    set_target_properties(${_target} PROPERTIES
      VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR})
  endif()
  get_target_property(_dir ${_target} SOURCE_DIR)
  get_target_property(_header_dirs ${_target} HEMIVEM_HEADER_DIRS)
  if(NOT _header_dirs AND EXISTS "${_dir}/include/hemivem")
    set(_header_dirs "${_dir}/include/hemivem")
  endif()
  foreach(_header_dir IN LISTS _header_dirs)
    install(DIRECTORY "${_header_dir}" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
            COMPONENT hemivem_development FILES_MATCHING PATTERN "*.hpp")
  endforeach()
endforeach()

install(TARGETS ${_hemivem_exported} EXPORT hemivemTargets
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT hemivemTargets NAMESPACE hemivem:: DESTINATION ${HEMIVEM_INSTALL_CMAKEDIR})
install(TARGETS hemivem RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# The package config, its version file (SameMajorVersion) and the Find modules a static
# build's config needs for CHOLMOD and MUMPS (neither ships a CMake config on Debian).
set(HEMIVEM_SHARED_LIBS ${BUILD_SHARED_LIBS})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hemivemConfig.cmake.in
  "${PROJECT_BINARY_DIR}/hemivemConfig.cmake"
  INSTALL_DESTINATION ${HEMIVEM_INSTALL_CMAKEDIR})
write_basic_package_version_file("${PROJECT_BINARY_DIR}/hemivemConfigVersion.cmake"
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/hemivemConfig.cmake" "${PROJECT_BINARY_DIR}/hemivemConfigVersion.cmake"
              ${PROJECT_SOURCE_DIR}/cmake/FindCHOLMOD.cmake ${PROJECT_SOURCE_DIR}/cmake/FindMUMPS.cmake
        DESTINATION ${HEMIVEM_INSTALL_CMAKEDIR})
message(STATUS "hemivem package components: ${HEMIVEM_BUILT_COMPONENTS}")

# hemivem_product: everything installed (the libraries, the command, the mumps-mpi module) and
# the Python module; what scripts/build.sh builds. scripts/test.sh builds the rest (the tests,
# the benchmarks, the fuzzers) before running them.
add_custom_target(hemivem_product)
foreach(_target IN LISTS _hemivem_exported ITEMS hemivem hemivem_linear_mumps_mpi_plugin hemivem_python)
  if(TARGET ${_target})
    get_target_property(_type ${_target} TYPE)
    if(NOT _type STREQUAL "INTERFACE_LIBRARY")
      add_dependencies(hemivem_product ${_target})
    endif()
  endif()
endforeach()
