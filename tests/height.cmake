# The height-above-ground colour mode against the CPU ground model (GL, llvmpipe).
sta_add_test(height SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_height.c
             LIBS sta_render sta_test_scene LABELS gl)
