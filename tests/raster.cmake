# The geometry pass's rasterisers (compute and GL_POINTS) against their C twin, on
# headless EGL + llvmpipe; the rasteriser choice without GL.
sta_add_test(raster SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_raster.c
             LIBS sta_render sta_test_scene LABELS gl)
