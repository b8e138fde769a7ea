# SPDX-License-Identifier: MIT
# Writes OUTPUT, a C file holding every shader in SHADER_DIR as a string, so the
# programs do not depend on where the source tree is. Run by the build (see
# src/CMakeLists.txt) whenever a shader changes.
file(GLOB shaders RELATIVE ${SHADER_DIR} ${SHADER_DIR}/*.vert ${SHADER_DIR}/*.frag
     ${SHADER_DIR}/*.comp ${SHADER_DIR}/*.geom ${SHADER_DIR}/*.glsl)
list(SORT shaders)
set(body "/* Generated from shaders/ by cmake/embed_shaders.cmake. Do not edit. */\n")
string(APPEND body "#include \"render/shader_source.h\"\n\n")
set(table "")
set(index 0)
foreach(name ${shaders})
    file(READ ${SHADER_DIR}/${name} hex HEX)
    string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," hex "${hex}")
    string(APPEND body "static const unsigned char shader_${index}[] = { ${hex} 0x00 };\n")
    string(APPEND table "    { \"${name}\", (const char *)shader_${index} },\n")
    math(EXPR index "${index} + 1")
endforeach()
string(APPEND body "\nconst sta_shader_source sta_shader_sources[] = {\n${table}    { 0, 0 }\n};\n")
file(WRITE ${OUTPUT}.tmp "${body}")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
