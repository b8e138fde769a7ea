# SPDX-License-Identifier: MIT
# The viewer's default camera (src/app/view_setup.c and view_sample.c, compiled in).
sta_add_test(view_setup SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_view_setup.c
             ${PROJECT_SOURCE_DIR}/src/app/view_setup.c ${PROJECT_SOURCE_DIR}/src/app/view_sample.c
             LIBS sta_render sta_preprocess sta_synth)
sta_module_root(test_view_setup app)
# The printed default camera, given back, shows the default view (headless EGL).
add_test(NAME view_setup.default_camera_given_back
         COMMAND ${PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_default_camera.py
                 ${PROJECT_BINARY_DIR})
set_tests_properties(view_setup.default_camera_given_back PROPERTIES LABELS gl)
