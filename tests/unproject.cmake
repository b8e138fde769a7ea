sta_add_test(unproject SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_unproject.c LIBS sta_render
             LABELS gl)
