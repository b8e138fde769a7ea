# SPDX-License-Identifier: MIT
# Mirror planes (src/mirror): geometry far from the origin, the file and its errors,
# the ghost models; and the synthetic mirror scene's ghosts against its truth.
sta_add_test(mirror SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_mirror.c LIBS sta_mirror)
