sta_add_test(navigation SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_navigation.c LIBS sta_render)
# strata-view in a real window under Xvfb (resize, idle, keys), driven with xdotool.
add_test(NAME navigation.window_resize_idle_keys
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_window.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/window)
set_tests_properties(navigation.window_resize_idle_keys PROPERTIES LABELS gl)
# R frames the default view again after a resize (Xvfb, xdotool).
add_test(NAME navigation.window_home_after_resize
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_window_home.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/window_home)
set_tests_properties(navigation.window_home_after_resize PROPERTIES LABELS gl)
