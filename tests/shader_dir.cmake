sta_add_test(shader_dir SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_shader_dir.c LIBS sta_render
             LABELS gl)
