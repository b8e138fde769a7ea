# GL tests of the HPR pass: headless EGL on Mesa llvmpipe (no GPU needed).
sta_add_test(hpr SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_hpr.c LIBS sta_render LABELS gl)
