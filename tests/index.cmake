sta_add_test(index SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_index.c LIBS sta_preprocess)
