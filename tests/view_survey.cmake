# SPDX-License-Identifier: MIT
# strata-view's surveyor options headless: --classes, --clip, --pick, --measure, --hud.
find_program(PYTHON3 python3 REQUIRED)
add_test(NAME view.survey_options
         COMMAND ${PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_view_survey.py ${PROJECT_BINARY_DIR})
set_tests_properties(view.survey_options PROPERTIES LABELS gl)
# The same tools in a real window under Xvfb, driven with xdotool (keys, Ctrl+click, J).
add_test(NAME view.window_survey_tools
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_window_survey.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/window_survey)
set_tests_properties(view.window_survey_tools PROPERTIES LABELS gl)
