# The splat pass (issue 12: oriented round disks, instanced and geometry-shader paths)
# against its C twin on headless EGL + llvmpipe; the splat arena beside the points.
sta_add_test(splats SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_splats.c
             LIBS sta_render sta_test_scene LABELS gl)
# strata-splat-probe (bench/splat_methods.sh) runs all three methods on a tiny case and
# behaves on the command line (--help, an unknown option).
add_test(NAME splats.probe_times_the_three_methods
         COMMAND strata-splat-probe --points 5000 --width 64 --height 48 --rounds 1 --repeat 1)
set_tests_properties(splats.probe_times_the_three_methods PROPERTIES LABELS gl
    PASS_REGULAR_EXPRESSION "instanced [0-9.]+ ms, geometry [0-9.]+ ms, pulled [0-9.]+ ms")
add_test(NAME splats.probe_cli
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_cli.sh $<TARGET_FILE:strata-splat-probe>)
set_tests_properties(splats.probe_cli PROPERTIES LABELS unit)
# The window keys (O, [ and ]) under Xvfb, driven with xdotool.
add_test(NAME splats.window_keys
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_window_splats.sh ${PROJECT_BINARY_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/window_splats)
set_tests_properties(splats.window_keys PROPERTIES LABELS gl)
