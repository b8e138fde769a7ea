sta_add_test(byte_planes SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_byte_planes.c LIBS sta_preprocess)
