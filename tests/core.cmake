sta_add_test(core SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_core.c LIBS sta_core)
