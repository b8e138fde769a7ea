# The viewer's live Katz mode (render/pass_katz.h) on llvmpipe through headless EGL.
sta_add_test(katz_view SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_katz_view.c
             LIBS sta_render sta_test_scene LABELS gl)
