/* SPDX-License-Identifier: MIT
 * OpenGL plumbing. */
#include "render/gl.h"

#include <epoxy/egl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/file_map.h"
#include "render/bindings.h"
#include "render/shader_source.h"

// The surfaceless platform (Mesa's llvmpipe, the CI's driver; NVIDIA's 580 has it too);
// where an EGL lacks it, the first EGL device (EGL_EXT_platform_device).
static char headless_platform[32]; // "surfaceless" or "device N": for sta_gl_describe

static EGLDisplay open_headless_display(void)
{
    EGLint major = 0, minor = 0;
    EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (display != EGL_NO_DISPLAY && eglInitialize(display, &major, &minor)) {
        snprintf(headless_platform, sizeof(headless_platform), "surfaceless");
        return display;
    }
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration") &&
        !epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_base")) {
        return EGL_NO_DISPLAY;
    }
    EGLDeviceEXT devices[8];
    EGLint device_count = 0;
    if (!eglQueryDevicesEXT(8, devices, &device_count)) {
        return EGL_NO_DISPLAY;
    }
    for (EGLint i = 0; i < device_count; i++) {
        display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
        if (display != EGL_NO_DISPLAY && eglInitialize(display, &major, &minor)) {
            snprintf(headless_platform, sizeof(headless_platform), "device %d", (int)i);
            return display;
        }
    }
    return EGL_NO_DISPLAY;
}

sta_status sta_gl_headless_create(sta_gl_headless *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    EGLDisplay display = open_headless_display();
    if (display == EGL_NO_DISPLAY) {
        return sta_fail(err, STA_ERR_GL,
                        "cannot open a headless EGL display, neither surfaceless nor on a device "
                        "(EGL error 0x%x); is Mesa's libegl-mesa0 (or a GPU's EGL driver) "
                        "installed?",
                        (unsigned)eglGetError());
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        eglTerminate(display);
        return sta_fail(err, STA_ERR_GL, "EGL cannot bind the OpenGL API (0x%x)",
                        (unsigned)eglGetError());
    }
    const EGLint config_attributes[] = { EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                         EGL_OPENGL_BIT, EGL_NONE };
    EGLConfig config = NULL;
    EGLint config_count = 0;
    eglChooseConfig(display, config_attributes, &config, 1, &config_count);
    const EGLint context_attributes[] = { EGL_CONTEXT_MAJOR_VERSION,
                                          4,
                                          EGL_CONTEXT_MINOR_VERSION,
                                          5,
                                          EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                          EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                          EGL_NONE };
    EGLContext context = eglCreateContext(display, config_count ? config : EGL_NO_CONFIG_KHR,
                                          EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT) {
        EGLint e = eglGetError();
        eglTerminate(display);
        return sta_fail(err, STA_ERR_GL, "cannot create an OpenGL 4.5 core context (EGL 0x%x)",
                        (unsigned)e);
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        EGLint e = eglGetError();
        eglDestroyContext(display, context);
        eglTerminate(display);
        return sta_fail(err, STA_ERR_GL, "cannot make the EGL context current (0x%x)", (unsigned)e);
    }
    out->display = display;
    out->context = context;
    return STA_OK;
}

void sta_gl_headless_destroy(sta_gl_headless *gl)
{
    if (!gl->display) {
        return;
    }
    eglMakeCurrent(gl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(gl->display, gl->context);
    // The display stays initialised: eglTerminate would unload Mesa's driver, whose
    // allocations LeakSanitizer then reports without symbols to suppress them by, and
    // the display is shared by every context of the process anyway.
    memset(gl, 0, sizeof(*gl));
}

// STRATA_SHADER_DIR: a folder whose files replace the embedded shaders of the same name
// (shader work on another driver without rebuilding; docs/VIEWER.md). Read once a
// name, kept for the process's life.
static const char *override_source(const char *name)
{
    static struct {
        char name[64];
        char *text;
    } cache[128];
    static int cached;
    const char *dir = getenv("STRATA_SHADER_DIR");
    if (!dir || !*dir || strlen(name) >= sizeof(cache[0].name)) {
        return NULL;
    }
    for (int i = 0; i < cached; i++) {
        if (strcmp(cache[i].name, name) == 0) {
            return cache[i].text;
        }
    }
    char path[4096];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    sta_file_map map = { 0 };
    sta_error ignored = { 0 };
    if (cached == (int)(sizeof(cache) / sizeof(cache[0])) ||
        sta_file_map_open(path, &map, &ignored) != STA_OK) {
        return NULL; // not there: the embedded shader
    }
    char *text = sta_malloc(map.size + 1);
    if (text) {
        if (map.size) {
            memcpy(text, map.data, map.size);
        }
        text[map.size] = 0;
    }
    sta_file_map_close(&map);
    if (!text) {
        return NULL;
    }
    snprintf(cache[cached].name, sizeof(cache[cached].name), "%s", name);
    cache[cached++].text = text;
    fprintf(stderr, "strata: shader %s read from %s\n", name, path);
    return text;
}

static const char *find_source(const char *name)
{
    const char *override = override_source(name);
    if (override) {
        return override;
    }
    for (const sta_shader_source *s = sta_shader_sources; s->name; s++) {
        if (strcmp(s->name, name) == 0) {
            return s->text;
        }
    }
    return NULL;
}

static GLenum stage_of(const char *name)
{
    const char *dot = strrchr(name, '.');
    if (dot && strcmp(dot, ".vert") == 0) {
        return GL_VERTEX_SHADER;
    }
    if (dot && strcmp(dot, ".frag") == 0) {
        return GL_FRAGMENT_SHADER;
    }
    if (dot && strcmp(dot, ".comp") == 0) {
        return GL_COMPUTE_SHADER;
    }
    if (dot && strcmp(dot, ".geom") == 0) {
        return GL_GEOMETRY_SHADER;
    }
    return 0;
}

// "#version 450 core" + one #define per entry of STA_BINDING_DEFINES, built by the
// preprocessor: each value is spelled as bindings.h spells it. Joined once at run time:
// as one literal it outgrew the 4095 characters C99 promises.
#define STRINGIFY(text)  #text
#define VALUE_TEXT(name) STRINGIFY(name)
static const char *const preamble_lines[] = { "#version 450 core\n",
#define X(name) "#define " #name " " VALUE_TEXT(name) "\n",
                                              STA_BINDING_DEFINES
#undef X
};
static char preamble[8192];
static pthread_once_t preamble_once = PTHREAD_ONCE_INIT;

static void join_preamble(void)
{
    size_t used = 0;
    for (size_t i = 0; i < sizeof(preamble_lines) / sizeof(preamble_lines[0]); i++) {
        size_t n = strlen(preamble_lines[i]);
        if (used + n >= sizeof(preamble)) {
            abort(); // bindings.h outgrew the buffer: a programming error, caught by every GL test
        }
        memcpy(preamble + used, preamble_lines[i], n);
        used += n;
    }
    preamble[used] = '\0';
}

sta_status sta_gl_program_create(const char *const *names, size_t count, const char *extra_defines,
                                 GLuint *out_program, sta_error *err)
{
    *out_program = 0;
    // ".glsl" names are shared function libraries, inserted before every stage.
    enum {
        MAX_PARTS = 16
    };
    const char *parts[MAX_PARTS];
    int part_count = 0;
    pthread_once(&preamble_once, join_preamble);
    parts[part_count++] = preamble;
    if (extra_defines) {
        parts[part_count++] = extra_defines;
        parts[part_count++] = "\n";
    }
    for (size_t i = 0; i < count; i++) {
        if (stage_of(names[i]) == 0) {
            const char *text = find_source(names[i]);
            if (!text || part_count >= MAX_PARTS - 1) {
                return sta_fail(err, STA_ERR_ARG, "no embedded shader library named %s", names[i]);
            }
            parts[part_count++] = text;
        }
    }
    GLuint program = glCreateProgram();
    sta_status status = STA_OK;
    for (size_t i = 0; i < count && status == STA_OK; i++) {
        GLenum stage = stage_of(names[i]);
        if (stage == 0) {
            continue;
        }
        const char *text = find_source(names[i]);
        if (!text) {
            status = sta_fail(err, STA_ERR_ARG, "no embedded shader named %s", names[i]);
            break;
        }
        GLuint shader = glCreateShader(stage);
        parts[part_count] = text;
        glShaderSource(shader, part_count + 1, parts, NULL);
        glCompileShader(shader);
        GLint ok = 0;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char log[1024] = { 0 };
            glGetShaderInfoLog(shader, sizeof(log), NULL, log);
            status = sta_fail(err, STA_ERR_GL, "shader %s does not compile: %s", names[i], log);
        } else {
            glAttachShader(program, shader);
        }
        glDeleteShader(shader); // freed when the program goes
    }
    if (status == STA_OK) {
        glLinkProgram(program);
        GLint ok = 0;
        glGetProgramiv(program, GL_LINK_STATUS, &ok);
        if (!ok) {
            char log[1024] = { 0 };
            glGetProgramInfoLog(program, sizeof(log), NULL, log);
            status = sta_fail(err, STA_ERR_GL, "program %s does not link: %s", names[0], log);
        }
    }
    if (status != STA_OK) {
        glDeleteProgram(program);
        return status;
    }
    *out_program = program;
    return STA_OK;
}

sta_status sta_gl_check(const char *what, sta_error *err)
{
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) {
        return STA_OK;
    }
    while (glGetError() != GL_NO_ERROR) {
    }
    return sta_fail(err, STA_ERR_GL, "%s: OpenGL error 0x%x", what, (unsigned)e);
}

const char *sta_gl_describe(char *buf, size_t size)
{
    snprintf(buf, size, "%s | %s%s%s", (const char *)glGetString(GL_RENDERER),
             (const char *)glGetString(GL_VERSION), headless_platform[0] ? " | EGL " : "",
             headless_platform);
    return buf;
}

void sta_gl_finish(void)
{
    glFinish();
}
