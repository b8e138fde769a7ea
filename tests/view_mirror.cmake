# SPDX-License-Identifier: MIT
# The viewer's mirror-marking tool (src/app/view_mirror_tool.c, compiled in, no GLFW).
sta_add_test(view_mirror SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_view_mirror.c
             ${PROJECT_SOURCE_DIR}/src/app/view_mirror_tool.c LIBS sta_stream)
sta_module_root(test_view_mirror app)
# The tool in a real window under Xvfb, driven with xdotool (O, Ctrl+click, Backspace,
# Enter, V).
add_test(NAME view_mirror.window_mirror_tool
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_window_mirror.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/window_mirror)
set_tests_properties(view_mirror.window_mirror_tool PROPERTIES LABELS gl)
# The mirror options headless: --mirrors (at load = stored), --show-ghosts, reflections,
# a bad file.
add_test(NAME view_mirror.headless_options
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_view_mirrors.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/view_mirrors)
set_tests_properties(view_mirror.headless_options PROPERTIES LABELS gl)
