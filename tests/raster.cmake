# The geometry pass's rasterisers (compute and GL_POINTS) against their C twin, on
# headless EGL + llvmpipe; the rasteriser choice without GL.
sta_add_test(raster SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_raster.c
             LIBS sta_render sta_test_scene LABELS gl)
# The one-pass 64-bit variant, which llvmpipe cannot build, checked by glslang.
add_test(NAME raster.packed_shaders_compile
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_packed_raster.sh
                 ${PROJECT_SOURCE_DIR}/shaders ${PROJECT_SOURCE_DIR}/src/render/bindings.h
                 ${PROJECT_SOURCE_DIR}/src/render/ref/screen_space.h
                 ${CMAKE_CURRENT_BINARY_DIR}/packed_raster)
set_tests_properties(raster.packed_shaders_compile PROPERTIES LABELS unit)
