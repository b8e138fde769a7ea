sta_add_test(knn_normals SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_knn_normals.c
             LIBS sta_preprocess sta_synth sta_stream LABELS unit)
