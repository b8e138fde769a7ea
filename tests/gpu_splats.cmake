sta_add_test(gpu_splats SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_gpu_splats.c LIBS sta_stream)
