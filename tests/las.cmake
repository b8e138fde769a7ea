sta_add_test(las SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_las.c LIBS sta_io)
