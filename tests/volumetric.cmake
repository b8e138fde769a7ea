sta_add_test(volumetric SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_volumetric.c LIBS sta_render
             LABELS gl)
