sta_add_test(laz SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_laz.c LIBS sta_io sta_preprocess sta_test_lazenc LABELS slow)
