sta_add_test(cell_blocks SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_cell_blocks.c
             LIBS sta_preprocess LABELS unit)
