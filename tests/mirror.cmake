# SPDX-License-Identifier: MIT
# Mirror planes (src/mirror): geometry far from the origin, the file and its errors,
# the ghost models; and the synthetic mirror scene's ghosts against its truth.
sta_add_test(mirror SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_mirror.c LIBS sta_synth sta_preprocess)
# mirror_ghosts: both ghost models against the mirror scene's truth (bench/mirror_ghosts.sh).
add_executable(mirror_ghosts ${CMAKE_CURRENT_SOURCE_DIR}/tools/mirror_ghosts_cli.c)
target_link_libraries(mirror_ghosts PRIVATE sta_synth)
