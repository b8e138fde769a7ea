sta_add_test(stream SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_stream.c LIBS sta_stream)
