sta_add_test(knn_grid SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_knn_grid.c LIBS sta_preprocess
             LABELS unit)
