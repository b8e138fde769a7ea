sta_add_test(laz_p14 SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_laz_p14.c LIBS sta_io sta_test_lazenc LABELS slow)
