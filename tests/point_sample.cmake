# CPU subsample of resident points for the live Katz mode (stream/point_sample.h). No GL.
sta_add_test(point_sample SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_point_sample.c
             LIBS sta_stream LABELS unit)
