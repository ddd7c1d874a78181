# FindCHOLMOD
# -----------
# Finds SuiteSparse's CHOLMOD (sparse Cholesky). SuiteSparse 5.x, as packaged by Debian
# bookworm (libsuitesparse-dev), ships neither a CMake config nor a pkg-config file, and
# puts its headers in <prefix>/include/suitesparse.
#
# Imported target:
#   CHOLMOD::CHOLMOD   cholmod with the libraries it needs: amd camd colamd ccolamd
#                      suitesparseconfig, METIS when present, BLAS and LAPACK
# Result variables:
#   CHOLMOD_FOUND, CHOLMOD_VERSION, CHOLMOD_INCLUDE_DIRS, CHOLMOD_LIBRARIES
# Hints: CHOLMOD_ROOT or SuiteSparse_ROOT (a prefix), or the cache variables
#   CHOLMOD_INCLUDE_DIR and CHOLMOD_<NAME>_LIBRARY.

include(FindPackageHandleStandardArgs)
include(FeatureSummary)

set(_cholmod_hints ${CHOLMOD_ROOT} $ENV{CHOLMOD_ROOT} ${SuiteSparse_ROOT} $ENV{SuiteSparse_ROOT})

find_path(CHOLMOD_INCLUDE_DIR NAMES cholmod.h
  HINTS ${_cholmod_hints}
  PATH_SUFFIXES include/suitesparse suitesparse include)

set(_cholmod_components cholmod amd camd colamd ccolamd suitesparseconfig)
set(_cholmod_required_libraries)
foreach(_lib IN LISTS _cholmod_components)
  string(TOUPPER ${_lib} _LIB)
  find_library(CHOLMOD_${_LIB}_LIBRARY NAMES ${_lib} HINTS ${_cholmod_hints} PATH_SUFFIXES lib lib64)
  mark_as_advanced(CHOLMOD_${_LIB}_LIBRARY)
  list(APPEND _cholmod_required_libraries CHOLMOD_${_LIB}_LIBRARY)
endforeach()
# METIS is needed only when linking CHOLMOD statically with its Partition module.
find_library(CHOLMOD_METIS_LIBRARY NAMES metis HINTS ${_cholmod_hints} PATH_SUFFIXES lib lib64)
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_METIS_LIBRARY)

if(CHOLMOD_INCLUDE_DIR AND EXISTS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h")
  file(STRINGS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h" _cholmod_version_lines
       REGEX "^#define[ \t]+CHOLMOD_(MAIN|SUB|SUBSUB)_VERSION[ \t]+[0-9]+")
  foreach(_part MAIN SUB SUBSUB)
    string(REGEX REPLACE ".*#define[ \t]+CHOLMOD_${_part}_VERSION[ \t]+([0-9]+).*" "\\1"
           _cholmod_${_part} "${_cholmod_version_lines}")
  endforeach()
  set(CHOLMOD_VERSION "${_cholmod_MAIN}.${_cholmod_SUB}.${_cholmod_SUBSUB}")
endif()

# CHOLMOD's supernodal factorization calls BLAS and LAPACK: the generic libblas/liblapack
# that Debian's CHOLMOD is built against, which the alternatives system points at the best
# BLAS installed (OpenBLAS when present). A vendor library found first (ATLAS's libf77blas)
# would be bound before it and keep CHOLMOD on that BLAS (docs/performance.md).
if(NOT DEFINED BLA_VENDOR)
  set(BLA_VENDOR Generic)
  set(_cholmod_reset_vendor TRUE)
endif()
if(NOT TARGET BLAS::BLAS)
  find_package(BLAS QUIET)
endif()
if(NOT TARGET LAPACK::LAPACK)
  find_package(LAPACK QUIET)
endif()
if(_cholmod_reset_vendor)
  unset(BLA_VENDOR)
  unset(_cholmod_reset_vendor)
endif()

find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR ${_cholmod_required_libraries}
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND)
  set(CHOLMOD_INCLUDE_DIRS ${CHOLMOD_INCLUDE_DIR})
  set(CHOLMOD_LIBRARIES ${CHOLMOD_CHOLMOD_LIBRARY} ${CHOLMOD_AMD_LIBRARY} ${CHOLMOD_CAMD_LIBRARY}
      ${CHOLMOD_COLAMD_LIBRARY} ${CHOLMOD_CCOLAMD_LIBRARY})
  if(CHOLMOD_METIS_LIBRARY)
    list(APPEND CHOLMOD_LIBRARIES ${CHOLMOD_METIS_LIBRARY})
  endif()
  list(APPEND CHOLMOD_LIBRARIES ${CHOLMOD_SUITESPARSECONFIG_LIBRARY})
  if(NOT TARGET CHOLMOD::CHOLMOD)
    add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
    set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
      IMPORTED_LOCATION "${CHOLMOD_CHOLMOD_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}")
    set(_cholmod_link ${CHOLMOD_AMD_LIBRARY} ${CHOLMOD_CAMD_LIBRARY} ${CHOLMOD_COLAMD_LIBRARY}
        ${CHOLMOD_CCOLAMD_LIBRARY})
    if(CHOLMOD_METIS_LIBRARY)
      list(APPEND _cholmod_link ${CHOLMOD_METIS_LIBRARY})
    endif()
    list(APPEND _cholmod_link ${CHOLMOD_SUITESPARSECONFIG_LIBRARY})
    if(TARGET LAPACK::LAPACK)
      list(APPEND _cholmod_link LAPACK::LAPACK)
    endif()
    if(TARGET BLAS::BLAS)
      list(APPEND _cholmod_link BLAS::BLAS)
    endif()
    set_property(TARGET CHOLMOD::CHOLMOD PROPERTY INTERFACE_LINK_LIBRARIES "${_cholmod_link}")
  endif()
endif()

set_package_properties(CHOLMOD PROPERTIES
  DESCRIPTION "SuiteSparse's sparse Cholesky factorization (supernodal)")
