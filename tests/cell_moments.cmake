sta_add_test(cell_moments SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_cell_moments.c
             LIBS sta_preprocess LABELS unit)
