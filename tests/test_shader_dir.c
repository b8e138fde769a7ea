/* SPDX-License-Identifier: MIT
 * STRATA_SHADER_DIR: files there replace embedded shaders of the same name (shader work
 * on another driver without rebuilding); a name found in neither is an error, and a
 * replacement that does not compile says which file and why. */
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/gl.h"

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_int_equal(fputs(text, f) >= 0, 1);
    assert_int_equal(fclose(f), 0);
}

// Runs `program` once (one invocation) and returns what it stored in word 0 of binding 0.
static unsigned run_store(GLuint program)
{
    GLuint buffer = 0;
    const GLuint zero = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, sizeof(GLuint), &zero, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
    glUseProgram(program);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint value = 0;
    glGetNamedBufferSubData(buffer, 0, sizeof(value), &value);
    glDeleteBuffers(1, &buffer);
    return value;
}

static void folder_replaces_and_adds_shaders(void **state)
{
    (void)state;
    sta_gl_headless gl = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_gl_headless_create(&gl, &err), STA_OK);
    const char *store = "layout(local_size_x = 1) in;\n"
                        "layout(std430, binding = 0) buffer Out { uint u_value; };\n"
                        "void main() { u_value = 4242u; }\n";
    write_text(sta_test_tmp_path("probe_store.comp"), store);
    write_text(sta_test_tmp_path("probe_broken.comp"), "void main() { not glsl }\n");
    assert_int_equal(setenv("STRATA_SHADER_DIR", sta_test_tmpdir(), 1), 0);

    GLuint program = 0;
    const char *names[] = { "probe_store.comp" };
    assert_int_equal(sta_gl_program_create(names, 1, NULL, &program, &err), STA_OK);
    assert_int_equal(run_store(program), 4242u);
    glDeleteProgram(program);

    const char *broken[] = { "probe_broken.comp" };
    assert_int_equal(sta_gl_program_create(broken, 1, NULL, &program, &err), STA_ERR_GL);
    assert_non_null(strstr(err.message, "probe_broken.comp does not compile"));

    const char *missing[] = { "probe_missing.comp" };
    assert_int_equal(sta_gl_program_create(missing, 1, NULL, &program, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "probe_missing.comp"));

    // Without the variable the embedded shaders serve again, and the probe is unknown.
    assert_int_equal(unsetenv("STRATA_SHADER_DIR"), 0);
    const char *later[] = { "probe_later.comp" };
    write_text(sta_test_tmp_path("probe_later.comp"), store);
    assert_int_equal(sta_gl_program_create(later, 1, NULL, &program, &err), STA_ERR_ARG);
    sta_gl_headless_destroy(&gl);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(folder_replaces_and_adds_shaders),
};

STA_TEST_MAIN(tests)
