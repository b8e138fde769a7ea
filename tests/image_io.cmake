sta_add_test(image_io SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_image_io.c LIBS sta_render)
target_include_directories(test_image_io PRIVATE ${OPENEXR_INCLUDE_DIR})
