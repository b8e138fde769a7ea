/* SPDX-License-Identifier: MIT
 * Volumetric classes shown as points: the GL passes. */
#include "render/pass_volumetric.h"

#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/ref/screen_space.h"

/* Listed tiles per row of the overlay's indirect dispatch. */
#define STA_VOLUMETRIC_TILE_ROW 64

sta_status sta_volumetric_pass_init(sta_volumetric_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    char defines[256];
    snprintf(defines, sizeof(defines),
             "#define STA_LABEL_VISIBLE %.1f\n#define STA_POSITION_W_MARKED %.1f\n"
             "#define STA_VOLUMETRIC_SPLAT_RADIUS_PX %d\n#define STA_VOLUMETRIC_TILE_ROW %d\n",
             (double)STA_LABEL_VISIBLE, (double)STA_POSITION_W_MARKED,
             STA_VOLUMETRIC_SPLAT_RADIUS_PX, STA_VOLUMETRIC_TILE_ROW);
    const char *mark[] = { "volumetric_mark.comp" };
    const char *overlay[] = { "volumetric_window.glsl", "volumetric_overlay.comp" };
    const char *tiles[] = { "volumetric_tiles.comp" };
    char image_defines[sizeof(defines) + 48];
    snprintf(image_defines, sizeof(image_defines), "%s#define STA_VOLUMETRIC_CLASS_IMAGE 1\n",
             defines);
    sta_status s = sta_gl_program_create(mark, 1, defines, &pass->mark_program, err);
    if (s == STA_OK) {
        s = sta_gl_program_create(mark, 1, image_defines, &pass->mark_image_program, err);
    }
    if (s == STA_OK) {
        s = sta_gl_program_create(overlay, 2, defines, &pass->overlay_program, err);
    }
    char flag_defines[sizeof(defines) + 32];
    snprintf(flag_defines, sizeof(flag_defines), "%s#define VW_FLAGS 1\n", defines);
    for (int v = 0; v < 2 && s == STA_OK; v++) {
        s = sta_gl_program_create(tiles, 1, v ? flag_defines : defines, &pass->tiles_programs[v],
                                  err);
    }
    if (s != STA_OK) {
        sta_volumetric_pass_release(pass);
        return s;
    }
    pass->mark_size = glGetUniformLocation(pass->mark_program, "u_size");
    pass->mark_classes = glGetUniformLocation(pass->mark_program, "u_classes");
    pass->mark_image_size = glGetUniformLocation(pass->mark_image_program, "u_size");
    pass->mark_image_classes = glGetUniformLocation(pass->mark_image_program, "u_classes");
    pass->overlay_size = glGetUniformLocation(pass->overlay_program, "u_size");
    for (int v = 0; v < 2; v++) {
        pass->tiles_size[v] = glGetUniformLocation(pass->tiles_programs[v], "u_size");
    }
    return STA_OK;
}

void sta_volumetric_pass_release(sta_volumetric_pass *pass)
{
    if (pass->mark_program) {
        glDeleteProgram(pass->mark_program);
    }
    if (pass->overlay_program) {
        glDeleteProgram(pass->overlay_program);
    }
    if (pass->mark_image_program) {
        glDeleteProgram(pass->mark_image_program);
    }
    for (int v = 0; v < 2; v++) {
        if (pass->tiles_programs[v]) {
            glDeleteProgram(pass->tiles_programs[v]);
        }
    }
    if (pass->tile_flags) {
        glDeleteTextures(1, &pass->tile_flags);
    }
    if (pass->nodes_buffer) {
        glDeleteBuffers(1, &pass->nodes_buffer);
    }
    if (pass->tile_buffer) {
        glDeleteBuffers(1, &pass->tile_buffer);
    }
    sta_free(pass->host_nodes);
    memset(pass, 0, sizeof(*pass));
}

sta_status sta_volumetric_points_from_cache(sta_volumetric_pass *pass, const sta_gpu_cache *cache,
                                            GLuint id_texture, sta_volumetric_points *out,
                                            sta_error *err)
{
    if (cache->node_count > pass->host_capacity) {
        uint32_t *table = sta_alloc_array(cache->node_count, 2 * sizeof(uint32_t));
        if (!table) {
            return sta_fail(err, STA_ERR_NOMEM, "volumetric node table: out of memory");
        }
        sta_free(pass->host_nodes);
        pass->host_nodes = table;
        pass->host_capacity = cache->node_count;
    }
    for (uint32_t i = 0; i < cache->node_count; i++) {
        const sta_gpu_cache_entry *e = &cache->entries[i];
        pass->host_nodes[2 * i] = e->is_resident ? e->offset : 0;
        pass->host_nodes[2 * i + 1] = e->is_resident ? e->count : 0;
    }
    *out =
        (sta_volumetric_points){ id_texture, cache->buffer, pass->host_nodes, cache->node_count };
    return STA_OK;
}

// The node table goes up every frame (8 bytes a node): offsets move when the arena is
// compacted, and a frame's uploads change residency.
static sta_status upload_nodes(sta_volumetric_pass *pass, const sta_volumetric_points *src,
                               sta_error *err)
{
    uint32_t count = src->node_count > 0 ? src->node_count : 1;
    if (count > pass->nodes_capacity) {
        if (pass->nodes_buffer) {
            glDeleteBuffers(1, &pass->nodes_buffer);
        }
        glCreateBuffers(1, &pass->nodes_buffer);
        glNamedBufferStorage(pass->nodes_buffer, (GLsizeiptr)count * 8, NULL,
                             GL_DYNAMIC_STORAGE_BIT);
        pass->nodes_capacity = count;
    }
    if (src->node_count > 0) {
        glNamedBufferSubData(pass->nodes_buffer, 0, (GLsizeiptr)src->node_count * 8, src->nodes);
    } else {
        static const uint32_t none[2] = { 0, 0 };
        glNamedBufferSubData(pass->nodes_buffer, 0, sizeof(none), none);
    }
    return sta_gl_check("volumetric node table", err);
}

sta_status sta_volumetric_pass_mark(sta_volumetric_pass *pass, const sta_volumetric_points *src,
                                    const uint32_t class_set[STA_VOLUMETRIC_CLASS_WORDS],
                                    GLuint class_texture, const sta_volumetric_frame *frame,
                                    sta_error *err)
{
    if (class_texture) {
        glUseProgram(pass->mark_image_program);
        glUniform2i(pass->mark_image_size, frame->width, frame->height);
        glUniform1uiv(pass->mark_image_classes, STA_VOLUMETRIC_CLASS_WORDS, class_set);
        glBindImageTexture(STA_VOLUMETRIC_MARK_IMAGE_CLASS, class_texture, 0, GL_FALSE, 0,
                           GL_READ_ONLY, GL_R8UI);
    } else {
        sta_status s = upload_nodes(pass, src, err);
        if (s != STA_OK) {
            return s;
        }
        glUseProgram(pass->mark_program);
        glUniform2i(pass->mark_size, frame->width, frame->height);
        glUniform1uiv(pass->mark_classes, STA_VOLUMETRIC_CLASS_WORDS, class_set);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_VOLUMETRIC_MARK_BUFFER_ARENA, src->arena);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_VOLUMETRIC_MARK_BUFFER_NODES,
                         pass->nodes_buffer);
    }
    if (src->id_texture) {
        glBindImageTexture(STA_VOLUMETRIC_MARK_IMAGE_ID, src->id_texture, 0, GL_FALSE, 0,
                           GL_READ_ONLY, GL_RG32UI);
    }
    glBindImageTexture(STA_VOLUMETRIC_MARK_IMAGE_POSITION, frame->position, 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_RGBA32F);
    sta_gl_dispatch_2d(frame->width, frame->height);
    return sta_gl_check("volumetric mark pass", err);
}

void sta_volumetric_window_bind(const sta_volumetric_frame *frame)
{
    glBindImageTexture(STA_VOLUMETRIC_WINDOW_IMAGE_POSITION, frame->position, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    glBindTextureUnit(STA_VOLUMETRIC_WINDOW_SAMPLER_COLOUR, frame->colour);
}

// The splat of a marked pixel reaches at most the 8 tiles around its own (VW_FLAGS).
_Static_assert(STA_VOLUMETRIC_SPLAT_RADIUS_PX <= STA_WORKGROUP_SIZE_X &&
                   STA_VOLUMETRIC_SPLAT_RADIUS_PX <= STA_WORKGROUP_SIZE_Y,
               "the overlay's tile flags assume a splat radius of at most a tile");

static int tile_count(int pixels, int tile)
{
    return (pixels + tile - 1) / tile;
}

sta_status sta_volumetric_pass_tile_flags(sta_volumetric_pass *pass, int width, int height,
                                          GLuint *out, sta_error *err)
{
    if (!pass->tile_flags || pass->flags_width != width || pass->flags_height != height) {
        if (pass->tile_flags) {
            glDeleteTextures(1, &pass->tile_flags);
        }
        glCreateTextures(GL_TEXTURE_2D, 1, &pass->tile_flags);
        glTextureStorage2D(pass->tile_flags, 1, GL_R32UI, tile_count(width, STA_WORKGROUP_SIZE_X),
                           tile_count(height, STA_WORKGROUP_SIZE_Y));
        pass->flags_width = width;
        pass->flags_height = height;
    }
    const GLuint zero = 0;
    glClearTexImage(pass->tile_flags, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    *out = pass->tile_flags;
    return sta_gl_check("volumetric tile flags", err);
}

sta_status sta_volumetric_pass_overlay(sta_volumetric_pass *pass, const sta_volumetric_frame *frame,
                                       bool flags_set, GLuint out, sta_error *err)
{
    GLuint tiles_x = (GLuint)tile_count(frame->width, STA_WORKGROUP_SIZE_X);
    GLuint tiles_y = (GLuint)tile_count(frame->height, STA_WORKGROUP_SIZE_Y);
    uint32_t tiles = tiles_x * tiles_y;
    if (!pass->tile_buffer || pass->tile_capacity < tiles) {
        if (pass->tile_buffer) {
            glDeleteBuffers(1, &pass->tile_buffer);
        }
        glCreateBuffers(1, &pass->tile_buffer);
        glNamedBufferStorage(pass->tile_buffer, (GLsizeiptr)(4 + (size_t)tiles) * sizeof(GLuint),
                             NULL, GL_DYNAMIC_STORAGE_BIT);
        pass->tile_capacity = tiles;
    }
    // Indirect dispatch (rows added as tiles are listed), then the count.
    const GLuint reset[4] = { STA_VOLUMETRIC_TILE_ROW, 0, 1, 0 };
    glNamedBufferSubData(pass->tile_buffer, 0, sizeof(reset), reset);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_VOLUMETRIC_TILES_BUFFER_LIST, pass->tile_buffer);
    sta_volumetric_window_bind(frame);
    int v = flags_set && pass->tile_flags && pass->flags_width == frame->width &&
                    pass->flags_height == frame->height
                ? 1
                : 0;
    if (v) {
        glBindImageTexture(STA_VOLUMETRIC_TILES_IMAGE_FLAGS, pass->tile_flags, 0, GL_FALSE, 0,
                           GL_READ_ONLY, GL_R32UI);
    }
    glUseProgram(pass->tiles_programs[v]);
    glUniform2i(pass->tiles_size[v], frame->width, frame->height);
    sta_gl_dispatch_2d((int)tiles_x, (int)tiles_y); // one invocation per tile
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);

    glUseProgram(pass->overlay_program);
    glUniform2i(pass->overlay_size, frame->width, frame->height);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_VOLUMETRIC_OVERLAY_BUFFER_TILES,
                     pass->tile_buffer);
    glBindImageTexture(STA_VOLUMETRIC_OVERLAY_IMAGE_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       GL_RGBA8);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pass->tile_buffer);
    glDispatchComputeIndirect(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_VOLUMETRIC_OVERLAY_BUFFER_TILES, 0);
    return sta_gl_check("volumetric overlay", err);
}
