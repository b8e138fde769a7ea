# SPDX-License-Identifier: MIT
# Mirror rendering (render/pass_mirror.c) headless on llvmpipe: the mirror region of the
# synthetic room against a render of the real geometry from the mirrored camera.
sta_add_test(mirror_render SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_mirror_render.c
             LIBS sta_test_scene sta_synth LABELS gl)
