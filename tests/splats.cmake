# The splat pass (issue 12: oriented round disks, instanced and geometry-shader paths)
# against its C twin on headless EGL + llvmpipe; the splat arena beside the points.
sta_add_test(splats SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_splats.c
             LIBS sta_render sta_test_scene LABELS gl)
