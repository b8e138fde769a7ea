# The architecture's rules beyond the include roots: no file loops, unique names, GL only
# in render/, binding numbers only from bindings.h (docs/ARCHITECTURE.md).
find_program(PYTHON3 python3 REQUIRED)
add_test(NAME architecture.rules
         COMMAND ${PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_architecture.py
                 ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR})
set_tests_properties(architecture.rules PROPERTIES LABELS unit)
