# Debian's SuiteSparse 5.12 ships neither a CMake config nor a .pc file: find the pieces by hand.
find_path(SuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
set(_ss_libs cholmod umfpack klu amd colamd camd ccolamd btf suitesparseconfig)
set(SuiteSparse_LIBRARIES)
foreach(lib ${_ss_libs})
  find_library(SuiteSparse_${lib}_LIBRARY ${lib})
  if(SuiteSparse_${lib}_LIBRARY)
    list(APPEND SuiteSparse_LIBRARIES ${SuiteSparse_${lib}_LIBRARY})
  endif()
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse REQUIRED_VARS SuiteSparse_INCLUDE_DIR
  SuiteSparse_klu_LIBRARY SuiteSparse_umfpack_LIBRARY SuiteSparse_cholmod_LIBRARY
  SuiteSparse_suitesparseconfig_LIBRARY)
if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::SuiteSparse)
  add_library(SuiteSparse::SuiteSparse INTERFACE IMPORTED)
  set_target_properties(SuiteSparse::SuiteSparse PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${SuiteSparse_LIBRARIES};lapack;blas")
endif()
