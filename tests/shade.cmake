sta_add_test(shade SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_shade.c LIBS sta_render LABELS gl)
