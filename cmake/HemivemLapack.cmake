# hemivem_link_lapack(TARGET DEFINITION): links TARGET privately against the generic LAPACK
# (the one CHOLMOD is built against: OpenBLAS's where the alternatives system points it there;
# cmake/FindCHOLMOD.cmake says why not a vendor's) and defines DEFINITION for its sources, where
# LAPACK is found; otherwise the target keeps its Eigen fallback. The libraries' paths are linked
# rather than LAPACK::LAPACK, so that a static hemivem's export needs no imported target from its
# users.
function(hemivem_link_lapack target definition)
  if(NOT DEFINED BLA_VENDOR)
    set(BLA_VENDOR Generic)
  endif()
  find_package(LAPACK QUIET)
  if(LAPACK_FOUND)
    target_link_libraries(${target} PRIVATE ${LAPACK_LIBRARIES})
    target_compile_definitions(${target} PRIVATE ${definition})
  endif()
endfunction()
