sta_add_test(pipeline SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_pipeline.c
             LIBS sta_render sta_test_scene LABELS gl)
