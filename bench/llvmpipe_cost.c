/* SPDX-License-Identifier: MIT
 * What one compute-shader operation costs on the GL driver in use (issue 15, fourteenth
 * cost round): each probe is a 1920x1080 dispatch (8 x 8 workgroups) timed with the
 * process's CPU clock around glFinish, median of N repeats; then the cost of one tiny
 * (1 x 1) dispatch. Written to tell which rewrites of the screen-space passes can pay on
 * llvmpipe: image loads against texel fetches, RGBA32F stores against narrower ones,
 * per-lane atomics; and (issue 15, nineteenth round) vec4 stores into a storage buffer and
 * that buffer's copy into an RGBA32F texture, the two halves of the staged stores
 * (src/render/gl_staged.h). Not part of the build: bench/llvmpipe_cost.sh compiles and runs it.
 * usage: llvmpipe_cost [REPEATS]   (EGL_PLATFORM=surfaceless for a headless run) */
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum {
    W = 1920,
    H = 1080,
    MAX_REPEATS = 64
};

static double cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static GLuint program(const char *body)
{
    static const char *head =
        "#version 450\n"
        "#extension GL_ARB_shader_ballot : enable\n"
        "#extension GL_ARB_gpu_shader_int64 : enable\n"
        "layout(local_size_x = 8, local_size_y = 8) in;\n"
        "layout(binding = 0, rgba32f) readonly uniform image2D i4;\n"
        "layout(binding = 1, r32f) readonly uniform image2D i1;\n"
        "layout(binding = 2, rgba32f) writeonly uniform image2D o4;\n"
        "layout(binding = 3, r32f) writeonly uniform image2D o1;\n"
        "layout(binding = 4, rgba8) writeonly uniform image2D o8;\n"
        "layout(binding = 5, rgba8) readonly uniform image2D i8;\n"
        "layout(binding = 0) uniform sampler2D s4;\n" /* RGBA32F, 11 mip levels */
        "layout(binding = 1) uniform sampler2D s8;\n" /* RGBA8 */
        "layout(std430, binding = 0) buffer List { uint count; uint list[]; };\n"
        "layout(std430, binding = 1) buffer Staged { vec4 staged[]; };\n"
        "layout(std430, binding = 2) buffer StagedU { uint staged_u[]; };\n"
        "layout(binding = 6, rgba16f) writeonly uniform image2D o16;\n"
        "layout(binding = 7, rg32f) writeonly uniform image2D o2;\n"
        "uniform ivec2 u_offset[16];\n"
        "#define PIXEL ivec2 p = ivec2(gl_GlobalInvocationID.xy); "
        "if (p.x >= 1920 || p.y >= 1080) return;\n";
    const char *sources[2] = { head, body };
    GLuint s = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(s, 2, sources, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(s, sizeof(log), NULL, log);
        fprintf(stderr, "llvmpipe_cost: shader does not compile:\n%s\n%s\n", log, body);
        exit(1);
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, s);
    glLinkProgram(p);
    glDeleteShader(s);
    return p;
}

static GLuint texture(GLenum format, int levels)
{
    GLuint t;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, levels, format, W, H);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static const struct {
    const char *name, *body;
} probes[] = {
    { "empty (bounds test only)", "void main() { PIXEL }" },
    { "store RGBA32F", "void main() { PIXEL imageStore(o4, p, vec4(p.x)); }" },
    { "store RGBA16F", "void main() { PIXEL imageStore(o16, p, vec4(p.x)); }" },
    { "store RG32F", "void main() { PIXEL imageStore(o2, p, vec4(p.x)); }" },
    { "store vec4 into a storage buffer (staged)",
      "void main() { PIXEL staged[p.y * 1920 + p.x] = vec4(p.x); }" },
    { "store R32F", "void main() { PIXEL imageStore(o1, p, vec4(p.x)); }" },
    { "store RGBA8", "void main() { PIXEL imageStore(o8, p, vec4(p.x * 1e-3)); }" },
    { "store packUnorm4x8 into a storage buffer (staged RGBA8)",
      "void main() { PIXEL staged_u[p.y * 1920 + p.x] = packUnorm4x8(vec4(p.x * 1e-3)); }" },
    { "9 imageLoad RGBA32F + store R32F",
      "void main() { PIXEL float a = 0.0; for (int i = 0; i < 9; i++) {"
      " vec4 v = imageLoad(i4, p + ivec2(i % 3 - 1, i / 3 - 1)); a += v.z * v.w; }"
      " imageStore(o1, p, vec4(a)); }" },
    { "9 imageLoad R32F + store R32F",
      "void main() { PIXEL float a = 0.0; for (int i = 0; i < 9; i++) {"
      " a += imageLoad(i1, p + ivec2(i % 3 - 1, i / 3 - 1)).r; } imageStore(o1, p, vec4(a)); }" },
    { "9 imageLoad RGBA8 + store R32F",
      "void main() { PIXEL float a = 0.0; for (int i = 0; i < 9; i++) {"
      " vec4 v = imageLoad(i8, p + ivec2(i % 3 - 1, i / 3 - 1)); a += v.z * v.w; }"
      " imageStore(o1, p, vec4(a)); }" },
    { "9 texelFetch RGBA32F + store R32F",
      "void main() { PIXEL float a = 0.0; for (int i = 0; i < 9; i++) {"
      " vec4 v = texelFetch(s4, p + ivec2(i % 3 - 1, i / 3 - 1), 0); a += v.z * v.w; }"
      " imageStore(o1, p, vec4(a)); }" },
    { "9 texelFetch RGBA8 + store R32F",
      "void main() { PIXEL float a = 0.0; for (int i = 0; i < 9; i++) {"
      " vec4 v = texelFetch(s8, p + ivec2(i % 3 - 1, i / 3 - 1), 0); a += v.z * v.w; }"
      " imageStore(o1, p, vec4(a)); }" },
    { "8 texelFetch from mip levels 0-3 + store R32F",
      "void main() { PIXEL float a = 0.0; int k = 1 + ((p.x >> 3) & 3); for (int i = 0; i < 8;"
      " i++) { vec4 v = texelFetch(s4, (p >> k) + ivec2(i & 1, i >> 1), k - 1); a += v.z * v.w; }"
      " imageStore(o1, p, vec4(a)); }" },
    { "8 imageLoad at per-level offsets + store R32F",
      "void main() { PIXEL float a = 0.0; int k = 1 + ((p.x >> 3) & 3); for (int i = 0; i < 8;"
      " i++) { vec4 v = imageLoad(i4, u_offset[k] + (p >> k) + ivec2(i & 1, i >> 1));"
      " a += v.z * v.w; } imageStore(o1, p, vec4(a)); }" },
    { "atomicAdd per lane (3 in 4 lanes) + SSBO store",
      "void main() { PIXEL if (((p.x ^ p.y) & 3) != 0) { uint i = atomicAdd(count, 1u);"
      " list[i & 0xfffffu] = uint(p.x); } }" },
};

// Times (median of `repeats`, CPU ms) the copy of `buffer` into `texture` as a pixel unpack
// buffer of RGBA texels of `type`, W x H.
static void time_copy(GLuint buffer, GLuint texture, GLenum type, int repeats, const char *name)
{
    double copy[MAX_REPEATS];
    for (int r = 0; r < repeats; r++) {
        glFinish();
        double t = cpu_ms();
        glMemoryBarrier(GL_PIXEL_BUFFER_BARRIER_BIT);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffer);
        glTextureSubImage2D(texture, 0, 0, 0, W, H, GL_RGBA, type, NULL);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        glFinish();
        copy[r] = cpu_ms() - t;
    }
    qsort(copy, (size_t)repeats, sizeof(double), by_value);
    printf("%-48s %7.2f CPU ms (min %.2f, max %.2f)\n", name, copy[repeats / 2], copy[0],
           copy[repeats - 1]);
}

int main(int argc, char **argv)
{
    int repeats = argc > 1 ? atoi(argv[1]) : 7;
    if (repeats < 1 || repeats > MAX_REPEATS) {
        fprintf(stderr, "llvmpipe_cost: REPEATS must be 1..%d\n", MAX_REPEATS);
        return 2;
    }
    EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    EGLint attribs[] = { EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                         EGL_NONE };
    EGLint context_attribs[] = { EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE };
    EGLConfig config;
    EGLint configs = 0;
    EGLContext context = EGL_NO_CONTEXT;
    if (eglInitialize(display, NULL, NULL) && eglBindAPI(EGL_OPENGL_API) &&
        eglChooseConfig(display, attribs, &config, 1, &configs) && configs == 1) {
        context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
    }
    if (context == EGL_NO_CONTEXT ||
        !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        fprintf(stderr, "llvmpipe_cost: no OpenGL 4.5 context (try EGL_PLATFORM=surfaceless)\n");
        return 1;
    }
    printf("%s, %dx%d, median of %d\n", (const char *)glGetString(GL_RENDERER), W, H, repeats);
    GLuint textures[8] = { texture(GL_RGBA32F, 11), texture(GL_R32F, 1),  texture(GL_RGBA32F, 1),
                           texture(GL_R32F, 1),     texture(GL_RGBA8, 1), texture(GL_RGBA8, 1),
                           texture(GL_RGBA16F, 1),  texture(GL_RG32F, 1) };
    const GLenum formats[8] = { GL_RGBA32F, GL_R32F,  GL_RGBA32F, GL_R32F,
                                GL_RGBA8,   GL_RGBA8, GL_RGBA16F, GL_RG32F };
    for (GLuint unit = 0; unit < 8; unit++) {
        glBindImageTexture(unit, textures[unit], 0, GL_FALSE, 0, GL_READ_WRITE, formats[unit]);
    }
    glBindTextureUnit(0, textures[0]);
    glBindTextureUnit(1, textures[5]);
    GLuint list;
    glCreateBuffers(1, &list);
    glNamedBufferStorage(list, ((1 << 20) + 1) * sizeof(GLuint), NULL, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, list);
    // The staged stores' buffer (render/gl_staged.h), also the copy's source below.
    GLuint staged;
    glCreateBuffers(1, &staged);
    glNamedBufferStorage(staged, (GLsizeiptr)W * H * 16, NULL, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, staged);
    // The staged RGBA8 stores' buffer: one packed uint per texel.
    GLuint staged_u;
    glCreateBuffers(1, &staged_u);
    glNamedBufferStorage(staged_u, (GLsizeiptr)W * H * 4, NULL, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, staged_u);
    GLint offsets[32];
    for (int k = 0; k < 16; k++) {
        offsets[2 * k] = (k * 37) % 900;
        offsets[2 * k + 1] = (k * 13) % 500;
    }
    const int count = (int)(sizeof(probes) / sizeof(probes[0]));
    GLuint programs[sizeof(probes) / sizeof(probes[0])];
    for (int i = 0; i < count; i++) {
        programs[i] = program(probes[i].body);
        glProgramUniform2iv(programs[i], glGetUniformLocation(programs[i], "u_offset"), 16,
                            offsets);
    }
    double ms[sizeof(probes) / sizeof(probes[0])][MAX_REPEATS];
    for (int r = 0; r < repeats; r++) { // interleaved: every probe once per round
        for (int i = 0; i < count; i++) {
            glUseProgram(programs[i]);
            glFinish();
            double t0 = cpu_ms();
            glDispatchCompute(W / 8, (H + 7) / 8, 1);
            glMemoryBarrier(GL_ALL_BARRIER_BITS);
            glFinish();
            ms[i][r] = cpu_ms() - t0;
        }
    }
    for (int i = 0; i < count; i++) {
        qsort(ms[i], (size_t)repeats, sizeof(double), by_value);
        printf("%-48s %7.2f CPU ms (min %.2f, max %.2f)\n", probes[i].name, ms[i][repeats / 2],
               ms[i][0], ms[i][repeats - 1]);
    }
    // The staged stores' second half: the buffer copied into the texture (vec4 texels into
    // RGBA32F, packed RGBA8 texels into RGBA8).
    time_copy(staged, textures[2], GL_FLOAT, repeats, "storage buffer -> RGBA32F texture copy");
    time_copy(staged_u, textures[4], GL_UNSIGNED_BYTE, repeats,
              "storage buffer -> RGBA8 texture copy");
    glUseProgram(programs[0]);
    glFinish();
    double t0 = cpu_ms();
    enum {
        TINY = 500
    };
    for (int k = 0; k < TINY; k++) {
        glDispatchCompute(1, 1, 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    }
    glFinish();
    printf("%-48s %7.4f CPU ms each\n", "1x1 dispatch + memory barrier", (cpu_ms() - t0) / TINY);
    return 0;
}
