sta_add_test(laz_v1 SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_laz_v1.c LIBS sta_io sta_test_lazenc LABELS slow)
