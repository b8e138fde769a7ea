# Live Katz worker (visibility/katz_worker.h): front/back set hand-over without GL, also run
# under the thread sanitizer preset (docs/KATZ.md).
sta_add_test(katz_worker SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_katz_worker.c
             LIBS sta_visibility LABELS unit)
