# Optional SuiteSparse back ends (CHOLMOD, UMFPACK) as the INTERFACE target drape::suitesparse.
#
# Debian's SuiteSparse 5.12 ships no CMake package, so the headers and libraries are found here
# directly. CHOLMOD's supernodal module is GPL and UMFPACK is GPL too: they live in this separate
# target so that users of the header-only drape::drape are not bound by those licences.
# OpenBLAS is linked explicitly when present so drape can pin it to one thread (see
# include/drape/solvers/cholmod.hpp); CHOLMOD itself uses whatever libblas.so.3 provides.

find_path(DRAPE_SUITESPARSE_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(DRAPE_CHOLMOD_LIBRARY cholmod)
find_library(DRAPE_UMFPACK_LIBRARY umfpack)
find_library(DRAPE_SUITESPARSECONFIG_LIBRARY suitesparseconfig)
find_library(DRAPE_OPENBLAS_LIBRARY NAMES openblas)
mark_as_advanced(DRAPE_SUITESPARSE_INCLUDE_DIR DRAPE_CHOLMOD_LIBRARY DRAPE_UMFPACK_LIBRARY
                 DRAPE_SUITESPARSECONFIG_LIBRARY DRAPE_OPENBLAS_LIBRARY)

if(DRAPE_SUITESPARSE_INCLUDE_DIR AND DRAPE_CHOLMOD_LIBRARY AND DRAPE_UMFPACK_LIBRARY AND DRAPE_SUITESPARSECONFIG_LIBRARY)
  set(DRAPE_HAS_SUITESPARSE ON)
  add_library(drape_suitesparse INTERFACE)
  add_library(drape::suitesparse ALIAS drape_suitesparse)
  set_target_properties(drape_suitesparse PROPERTIES EXPORT_NAME suitesparse)
  target_include_directories(drape_suitesparse INTERFACE "${DRAPE_SUITESPARSE_INCLUDE_DIR}")
  target_link_libraries(drape_suitesparse INTERFACE drape::drape
    "${DRAPE_CHOLMOD_LIBRARY}" "${DRAPE_UMFPACK_LIBRARY}" "${DRAPE_SUITESPARSECONFIG_LIBRARY}")
  target_compile_definitions(drape_suitesparse INTERFACE DRAPE_HAS_SUITESPARSE=1)
  if(DRAPE_OPENBLAS_LIBRARY)
    target_link_libraries(drape_suitesparse INTERFACE "${DRAPE_OPENBLAS_LIBRARY}")
    target_compile_definitions(drape_suitesparse INTERFACE DRAPE_HAS_OPENBLAS=1)
  endif()
  install(TARGETS drape_suitesparse EXPORT drapeTargets)
  message(STATUS "drape: SuiteSparse found (${DRAPE_CHOLMOD_LIBRARY}); target drape::suitesparse available")
else()
  set(DRAPE_HAS_SUITESPARSE OFF)
  message(STATUS "drape: SuiteSparse (CHOLMOD/UMFPACK) not found; drape::suitesparse is not built "
                 "(header-only solvers cg, bicgstab, ldlt, lu remain)")
endif()
