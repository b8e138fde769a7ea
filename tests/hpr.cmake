# GL tests of the HPR pass: headless EGL on Mesa llvmpipe (no GPU needed).
sta_add_test(hpr SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_hpr.c LIBS sta_render LABELS gl)
# --hpr-gaps takes only blocks or smooth: both programs name a bad value and exit 2.
foreach(program strata-view strata-bench)
    add_test(NAME hpr.${program}_gaps_option_refuses_a_bad_value
             COMMAND sh -c "out=$(\"$0\" --hpr-gaps foo missing.strata 2>&1); rc=$?; echo \"$out\"; \
[ $rc -eq 2 ] && case \"$out\" in *\"--hpr-gaps takes blocks or smooth, got 'foo'\"*) exit 0 ;; esac; exit 1"
                     $<TARGET_FILE:${program}>)
    set_tests_properties(hpr.${program}_gaps_option_refuses_a_bad_value PROPERTIES LABELS unit)
endforeach()
