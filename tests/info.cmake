# strata-info: command-line behaviour and agreement with an independent LAS decoder.
find_program(PYTHON3 python3 REQUIRED)
add_test(NAME info.cli COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_cli.sh
         $<TARGET_FILE:strata-info>)
add_test(NAME info.points_match_independent_decoder
         COMMAND ${PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_info_points.py
                 $<TARGET_FILE:strata-info> ${STA_DEFAULT_SHARED_DATA})
set_tests_properties(info.cli info.points_match_independent_decoder PROPERTIES
    LABELS unit SKIP_RETURN_CODE 77)
add_test(NAME info.strata_points_match_the_las_input
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_info_strata_points.sh
                 $<TARGET_FILE:strata-info> $<TARGET_FILE:strata-convert> ${STA_DEFAULT_SHARED_DATA})
set_tests_properties(info.strata_points_match_the_las_input PROPERTIES
    LABELS unit SKIP_RETURN_CODE 77)
