sta_add_test(ply SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_ply.c LIBS sta_io)
