sta_add_test(convert SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_convert.c LIBS sta_preprocess)
