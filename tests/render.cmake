# GL tests: headless EGL on Mesa llvmpipe (no GPU needed).
sta_add_test(render SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_render.c
             LIBS sta_render sta_test_scene LABELS gl)
# Headless renders of the demo street against recorded hashes (restructuring changes no pixel).
add_test(NAME render.golden_demo_renders
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_golden_renders.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_SOURCE_DIR}/golden/renders.sha256 ${CMAKE_CURRENT_BINARY_DIR}/golden)
set_tests_properties(render.golden_demo_renders PROPERTIES LABELS gl)
