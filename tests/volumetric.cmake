# SPDX-License-Identifier: MIT
# Volumetric classes drawn as points (render/pass_volumetric.h): rule, shaders against
# the twin, the pipeline on a frame (gl); the --no-fill-classes option (unit).
sta_add_test(volumetric SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_volumetric.c LIBS sta_render sta_test_scene sta_synth
             LABELS gl)
add_test(NAME volumetric.view_option
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_view_no_fill.sh ${PROJECT_BINARY_DIR})
set_tests_properties(volumetric.view_option PROPERTIES LABELS unit)
