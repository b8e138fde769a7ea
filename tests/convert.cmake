sta_add_test(convert SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_convert.c LIBS sta_preprocess)
add_test(NAME convert.cli_compress_zero_stores
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_convert_cli.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/convert_cli)
set_tests_properties(convert.cli_compress_zero_stores PROPERTIES LABELS unit)
add_test(NAME convert.cli_normals_method
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_convert_normals_method.sh
                 ${PROJECT_BINARY_DIR} ${CMAKE_CURRENT_BINARY_DIR}/convert_normals_method)
set_tests_properties(convert.cli_normals_method PROPERTIES LABELS unit)
