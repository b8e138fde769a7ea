# GL tests: headless EGL on Mesa llvmpipe (no GPU needed).
sta_add_test(render SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_render.c
             LIBS sta_render sta_test_scene LABELS gl)
