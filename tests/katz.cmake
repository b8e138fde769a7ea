# Katz et al. HPR reference (Qhull): analytic visibility, degenerate input, determinism.
sta_add_test(katz SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_katz.c LIBS sta_visibility LABELS unit)
