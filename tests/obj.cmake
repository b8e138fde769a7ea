# SPDX-License-Identifier: MIT
# Wavefront OBJ meshes (src/io/obj.c) and a synth mesh scene from one.
sta_add_test(obj SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_obj.c LIBS sta_io sta_synth)
