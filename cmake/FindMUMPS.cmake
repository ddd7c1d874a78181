# FindMUMPS
# ---------
#
# Finds the double precision MUMPS sparse direct solver in its two builds, as separate
# components with separate imported targets:
#
#   seq  MUMPS::seq  the sequential build: dmumps_seq mumps_common_seq pord_seq mpiseq_seq,
#                    compiled against the fake mpi.h of its include folder mumps_seq/
#   mpi  MUMPS::mpi  the MPI build: dmumps mumps_common pord with MPI::MPI_C (MPI::MPI_CXX in a
#                    project without C) and ScaLAPACK when the link test needs it
#
#   find_package(MUMPS [COMPONENTS seq mpi] [OPTIONAL_COMPONENTS seq mpi])
#
# Without components both are looked for and either is enough for MUMPS_FOUND.
#
# The two builds export the same symbols (dmumps_c and the Fortran internals) and their
# include paths disagree on mpi.h: a program may contain one of them only. Both targets
# carry the string property MUMPS_FLAVOUR (seq or mpi) declared in COMPATIBLE_INTERFACE_STRING,
# so CMake stops with an error at generation time when one target links both.
#
# Result variables:
#   MUMPS_FOUND, MUMPS_seq_FOUND, MUMPS_mpi_FOUND, MUMPS_VERSION, MUMPS_INCLUDE_DIR,
#   MUMPS_SEQ_INCLUDE_DIR (the folder with the fake mpi.h), MUMPS_SEQ_LIBRARIES, MUMPS_MPI_LIBRARIES
#
# Every candidate set of libraries passes a link test (a program calling dmumps_c) before its
# target is created. The MPI build needs find_package(MPI); it is called here when the caller
# did not.

include(CheckCXXSourceCompiles)
include(CMakePushCheckState)
include(FindPackageHandleStandardArgs)

set(_mumps_components ${MUMPS_FIND_COMPONENTS})
if(NOT _mumps_components)
  set(_mumps_components seq mpi)
endif()
foreach(_c IN LISTS _mumps_components)
  if(NOT _c MATCHES "^(seq|mpi)$")
    message(FATAL_ERROR "FindMUMPS: unknown component '${_c}' (known: seq, mpi)")
  endif()
endforeach()

find_path(MUMPS_INCLUDE_DIR NAMES dmumps_c.h PATH_SUFFIXES mumps MUMPS
          DOC "Folder of dmumps_c.h (shared by both builds)")
mark_as_advanced(MUMPS_INCLUDE_DIR)

set(_mumps_header_ok FALSE)
if(MUMPS_INCLUDE_DIR AND EXISTS "${MUMPS_INCLUDE_DIR}/dmumps_c.h")
  set(_mumps_header_ok TRUE)
  file(STRINGS "${MUMPS_INCLUDE_DIR}/dmumps_c.h" _mumps_version_line
       REGEX "^#define[ \t]+MUMPS_VERSION[ \t]+\"[0-9.]+\"")
  if(_mumps_version_line MATCHES "\"([0-9.]+)\"")
    set(MUMPS_VERSION "${CMAKE_MATCH_1}")
  endif()
endif()

# Helper libraries a static or unusual MUMPS may need beyond the shared objects' own
# dependencies: LAPACK/BLAS, the gfortran runtime, threads.
function(_mumps_extra_libraries out)
  set(_extra)
  if(NOT TARGET LAPACK::LAPACK)
    find_package(LAPACK QUIET)
  endif()
  if(TARGET LAPACK::LAPACK)
    list(APPEND _extra LAPACK::LAPACK)
  endif()
  if(NOT MUMPS_GFORTRAN_LIBRARY)
    find_library(MUMPS_GFORTRAN_LIBRARY NAMES gfortran libgfortran.so.5)
    if(NOT MUMPS_GFORTRAN_LIBRARY AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libgfortran.so
                      OUTPUT_VARIABLE _gf OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      if(_gf AND IS_ABSOLUTE "${_gf}" AND EXISTS "${_gf}")
        set(MUMPS_GFORTRAN_LIBRARY "${_gf}" CACHE FILEPATH "gfortran runtime library" FORCE)
      endif()
    endif()
    mark_as_advanced(MUMPS_GFORTRAN_LIBRARY)
  endif()
  if(MUMPS_GFORTRAN_LIBRARY)
    list(APPEND _extra ${MUMPS_GFORTRAN_LIBRARY})
  endif()
  if(NOT TARGET Threads::Threads)
    find_package(Threads QUIET)
  endif()
  if(TARGET Threads::Threads)
    list(APPEND _extra Threads::Threads)
  endif()
  list(APPEND _extra m)
  set(${out} ${_extra} PARENT_SCOPE)
endfunction()

# _mumps_link_test(<result var> <test name> <includes> <libraries> <source>)
# The cached result is dropped when the includes or libraries change.
function(_mumps_link_test out name includes libraries source)
  set(_signature "${includes}|${libraries}")
  if(NOT "${_signature}" STREQUAL "${${name}_INPUTS}")
    unset(${name} CACHE)
    set(${name}_INPUTS "${_signature}" CACHE INTERNAL "inputs of the link test ${name}")
  endif()
  cmake_push_check_state(RESET)
  set(CMAKE_REQUIRED_QUIET ${MUMPS_FIND_QUIETLY})
  set(CMAKE_REQUIRED_INCLUDES ${includes})
  set(CMAKE_REQUIRED_LIBRARIES ${libraries})
  check_cxx_source_compiles("${source}" ${name})
  cmake_pop_check_state()
  set(${out} ${${name}} PARENT_SCOPE)
endfunction()

# ---- sequential build --------------------------------------------------------
set(MUMPS_seq_FOUND FALSE)
if("seq" IN_LIST _mumps_components AND _mumps_header_ok)
  find_path(MUMPS_SEQ_INCLUDE_PARENT NAMES mumps_seq/mpi.h HINTS "${MUMPS_INCLUDE_DIR}"
            DOC "Folder holding mumps_seq/ (the fake mpi.h of sequential MUMPS)")
  mark_as_advanced(MUMPS_SEQ_INCLUDE_PARENT)
  if(MUMPS_SEQ_INCLUDE_PARENT)
    set(MUMPS_SEQ_INCLUDE_DIR "${MUMPS_SEQ_INCLUDE_PARENT}/mumps_seq")
  endif()
  set(_seq_libs)
  set(_seq_missing FALSE)
  foreach(_l IN ITEMS dmumps_seq mumps_common_seq pord_seq mpiseq_seq)
    find_library(MUMPS_${_l}_LIBRARY NAMES ${_l})
    mark_as_advanced(MUMPS_${_l}_LIBRARY)
    if(MUMPS_${_l}_LIBRARY)
      list(APPEND _seq_libs ${MUMPS_${_l}_LIBRARY})
    else()
      set(_seq_missing TRUE)
    endif()
  endforeach()
  if(MUMPS_SEQ_INCLUDE_DIR AND NOT _seq_missing)
    set(_src "#include <mpi.h>
#include <dmumps_c.h>
int main() {
  DMUMPS_STRUC_C id{};
  id.job = -1; id.par = 1; id.sym = 1; id.comm_fortran = -987654;
  dmumps_c(&id);
  return 0;
}")
    set(_inc "${MUMPS_INCLUDE_DIR};${MUMPS_SEQ_INCLUDE_DIR}")
    _mumps_link_test(_ok MUMPS_SEQ_LINKS "${_inc}" "${_seq_libs}" "${_src}")
    set(_seq_extra)
    if(NOT _ok)
      _mumps_extra_libraries(_seq_extra)
      _mumps_link_test(_ok MUMPS_SEQ_LINKS_WITH_EXTRAS "${_inc}" "${_seq_libs};${_seq_extra}" "${_src}")
    endif()
    if(_ok)
      set(MUMPS_seq_FOUND TRUE)
      set(MUMPS_SEQ_LIBRARIES ${_seq_libs} ${_seq_extra})
      if(NOT TARGET MUMPS::seq)
        add_library(MUMPS::seq INTERFACE IMPORTED)
        set_target_properties(MUMPS::seq PROPERTIES
          INTERFACE_INCLUDE_DIRECTORIES "${MUMPS_INCLUDE_DIR};${MUMPS_SEQ_INCLUDE_DIR}"
          INTERFACE_LINK_LIBRARIES "${MUMPS_SEQ_LIBRARIES}"
          INTERFACE_MUMPS_FLAVOUR seq
          COMPATIBLE_INTERFACE_STRING MUMPS_FLAVOUR)
      endif()
    endif()
  endif()
endif()

# ---- MPI build ---------------------------------------------------------------
set(MUMPS_mpi_FOUND FALSE)
if("mpi" IN_LIST _mumps_components AND _mumps_header_ok)
  # MPI through its C component when C is enabled, else through the C++ one (a C++-only
  # project cannot find the C component).
  if(NOT TARGET MPI::MPI_C AND NOT TARGET MPI::MPI_CXX)
    get_property(_langs GLOBAL PROPERTY ENABLED_LANGUAGES)
    if("C" IN_LIST _langs)
      find_package(MPI QUIET COMPONENTS C)
    else()
      find_package(MPI QUIET COMPONENTS CXX)
    endif()
  endif()
  set(_mpi_target)
  if(TARGET MPI::MPI_C)
    set(_mpi_target MPI::MPI_C)
  elseif(TARGET MPI::MPI_CXX)
    set(_mpi_target MPI::MPI_CXX)
  endif()
  set(_mpi_libs)
  set(_mpi_missing FALSE)
  foreach(_l IN ITEMS dmumps mumps_common pord)
    find_library(MUMPS_${_l}_LIBRARY NAMES ${_l})
    mark_as_advanced(MUMPS_${_l}_LIBRARY)
    if(MUMPS_${_l}_LIBRARY)
      list(APPEND _mpi_libs ${MUMPS_${_l}_LIBRARY})
    else()
      set(_mpi_missing TRUE)
    endif()
  endforeach()
  if(_mpi_target AND NOT _mpi_missing)
    set(_src "#include <mpi.h>
#include <dmumps_c.h>
int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  DMUMPS_STRUC_C id{};
  id.job = -1; id.par = 1; id.sym = 1; id.comm_fortran = (MUMPS_INT)MPI_Comm_c2f(MPI_COMM_WORLD);
  dmumps_c(&id);
  MPI_Finalize();
  return 0;
}")
    _mumps_link_test(_ok MUMPS_MPI_LINKS "${MUMPS_INCLUDE_DIR}" "${_mpi_libs};${_mpi_target}" "${_src}")
    set(_mpi_extra)
    if(NOT _ok)
      find_library(MUMPS_SCALAPACK_LIBRARY NAMES scalapack-openmpi scalapack-mpich scalapack)
      mark_as_advanced(MUMPS_SCALAPACK_LIBRARY)
      if(MUMPS_SCALAPACK_LIBRARY)
        list(APPEND _mpi_extra ${MUMPS_SCALAPACK_LIBRARY})
      endif()
      _mumps_extra_libraries(_more)
      list(APPEND _mpi_extra ${_more})
      _mumps_link_test(_ok MUMPS_MPI_LINKS_WITH_EXTRAS "${MUMPS_INCLUDE_DIR}"
                       "${_mpi_libs};${_mpi_extra};${_mpi_target}" "${_src}")
    endif()
    if(_ok)
      set(MUMPS_mpi_FOUND TRUE)
      set(MUMPS_MPI_LIBRARIES ${_mpi_libs} ${_mpi_extra})
      if(NOT TARGET MUMPS::mpi)
        add_library(MUMPS::mpi INTERFACE IMPORTED)
        set_target_properties(MUMPS::mpi PROPERTIES
          INTERFACE_INCLUDE_DIRECTORIES "${MUMPS_INCLUDE_DIR}"
          INTERFACE_LINK_LIBRARIES "${MUMPS_MPI_LIBRARIES};${_mpi_target}"
          INTERFACE_MUMPS_FLAVOUR mpi
          COMPATIBLE_INTERFACE_STRING MUMPS_FLAVOUR)
      endif()
    endif()
  endif()
endif()

# Without required components, one build is enough.
if(MUMPS_seq_FOUND OR MUMPS_mpi_FOUND)
  set(MUMPS_ANY_BUILD_LINKS TRUE)
else()
  set(MUMPS_ANY_BUILD_LINKS FALSE)
endif()

find_package_handle_standard_args(MUMPS
  REQUIRED_VARS MUMPS_INCLUDE_DIR MUMPS_ANY_BUILD_LINKS
  VERSION_VAR MUMPS_VERSION
  HANDLE_COMPONENTS
  REASON_FAILURE_MESSAGE "neither the sequential nor the MPI build of MUMPS links")

unset(_mumps_components)
unset(_mumps_header_ok)
