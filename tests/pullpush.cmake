sta_add_test(pullpush SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_pullpush.c LIBS sta_render
             LABELS gl)
