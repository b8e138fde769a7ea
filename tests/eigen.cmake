# SPDX-License-Identifier: MIT
# The symmetric 3x3 eigen solver against LAPACK (liblapacke-dev; Debian 12 ships no
# pkg-config file for it, hence find_library / find_path).
find_library(LAPACKE_LIBRARY lapacke)
find_path(LAPACKE_INCLUDE_DIR lapacke.h)
if(LAPACKE_LIBRARY AND LAPACKE_INCLUDE_DIR)
    sta_add_test(eigen SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_eigen.c
                 LIBS sta_render ${LAPACKE_LIBRARY} ${M_LIBRARY} LABELS unit)
    target_include_directories(test_eigen PRIVATE ${LAPACKE_INCLUDE_DIR})
    # The GLSL twin runs on llvmpipe.
    set_tests_properties(eigen.glsl_matches_c_float PROPERTIES LABELS gl)
else()
    message(WARNING "LAPACKE not found (install liblapacke-dev): eigen tests are not built")
endif()
