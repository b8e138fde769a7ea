sta_add_test(knn_normals SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_knn_normals.c
             LIBS sta_preprocess sta_synth sta_stream LABELS unit)
# The accuracy table of bench/normals.sh against strata-synth truth (test tooling).
add_executable(normals_accuracy ${CMAKE_CURRENT_SOURCE_DIR}/tools/normals_accuracy.c)
target_link_libraries(normals_accuracy PRIVATE sta_synth sta_format ${M_LIBRARY})
