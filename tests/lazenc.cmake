sta_add_test(lazenc SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_lazenc.c LIBS sta_io sta_test_lazenc LABELS slow)
