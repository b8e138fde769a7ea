sta_add_test(key_slots SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_key_slots.c
             LIBS sta_preprocess LABELS unit)
