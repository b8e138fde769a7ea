/* SPDX-License-Identifier: MIT
 * PNG and OpenEXR output read back: every value survives. */
#include "test_support.h"

#include <math.h>
#include <openexr.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "render/image_io.h"

static void png_round_trip(void **state)
{
    (void)state;
    enum {
        W = 7,
        H = 5
    };
    uint8_t rgba[W * H * 4];
    for (int i = 0; i < W * H * 4; i++) {
        rgba[i] = (uint8_t)(i * 37);
    }
    const char *path = sta_test_tmp_path("t.png");
    sta_error err = { 0 };
    assert_int_equal(sta_png_write_rgba(path, rgba, W, H, &err), STA_OK);
    uint8_t *back = NULL;
    int w = 0, h = 0;
    assert_int_equal(sta_png_read_rgba(path, &back, &w, &h, &err), STA_OK);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    assert_memory_equal(back, rgba, sizeof(rgba));
    sta_free(back);
    assert_int_equal(sta_png_write_rgba("/nonexistent/dir/x.png", rgba, W, H, &err), STA_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/dir/x.png"));
}

// Reads one FLOAT channel of a scanline EXR with the OpenEXR core API.
static void read_channel(const char *path, const char *name, int w, int h, float *out)
{
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    assert_int_equal(exr_start_read(&ctx, path, &init), EXR_ERR_SUCCESS);
    const exr_attr_chlist_t *channels = NULL;
    assert_int_equal(exr_get_channels(ctx, 0, &channels), EXR_ERR_SUCCESS);
    int found = 0;
    for (int c = 0; c < channels->num_channels; c++) {
        found |= strcmp(channels->entries[c].name.str, name) == 0;
    }
    assert_true(found);
    int32_t lines = 0;
    assert_int_equal(exr_get_scanlines_per_chunk(ctx, 0, &lines), EXR_ERR_SUCCESS);
    exr_decode_pipeline_t decoder;
    memset(&decoder, 0, sizeof(decoder));
    int ready = 0;
    for (int y = 0; y < h; y += lines) {
        exr_chunk_info_t chunk;
        assert_int_equal(exr_read_scanline_chunk_info(ctx, 0, y, &chunk), EXR_ERR_SUCCESS);
        assert_int_equal(ready ? exr_decoding_update(ctx, 0, &chunk, &decoder)
                               : exr_decoding_initialize(ctx, 0, &chunk, &decoder),
                         EXR_ERR_SUCCESS);
        ready = 1;
        for (int16_t c = 0; c < decoder.channel_count; c++) {
            exr_coding_channel_info_t *info = &decoder.channels[c];
            int mine = strcmp(info->channel_name, name) == 0;
            // Channels we skip still need a destination: a scratch line.
            static float scratch[4096];
            info->decode_to_ptr =
                mine ? (uint8_t *)(out + (size_t)y * (size_t)w) : (uint8_t *)scratch;
            info->user_pixel_stride = sizeof(float);
            info->user_line_stride = mine ? (int32_t)(sizeof(float) * (size_t)w) : 0;
            info->user_bytes_per_element = sizeof(float);
            info->user_data_type = EXR_PIXEL_FLOAT;
        }
        assert_int_equal(exr_decoding_choose_default_routines(ctx, 0, &decoder), EXR_ERR_SUCCESS);
        assert_int_equal(exr_decoding_run(ctx, 0, &decoder), EXR_ERR_SUCCESS);
    }
    exr_decoding_destroy(ctx, &decoder);
    exr_finish(&ctx);
}

static void exr_round_trip(void **state)
{
    (void)state;
    enum {
        W = 13,
        H = 9
    };
    float *a = malloc(sizeof(float) * W * H), *b = malloc(sizeof(float) * W * H);
    float *back = malloc(sizeof(float) * W * H);
    assert_true(a && b && back);
    for (int i = 0; i < W * H; i++) {
        a[i] = (float)i * 0.25f - 3.0f;
        b[i] = i % 5 == 0 ? INFINITY : 1.0f / (float)(i + 1); // Z with empty pixels
    }
    const sta_exr_channel channels[2] = { { "Z", b }, { "N.X", a } };
    const char *path = sta_test_tmp_path("t.exr");
    sta_error err = { 0 };
    assert_int_equal(sta_exr_write(path, channels, 2, W, H, &err), STA_OK);
    read_channel(path, "N.X", W, H, back);
    assert_memory_equal(back, a, sizeof(float) * W * H);
    read_channel(path, "Z", W, H, back);
    for (int i = 0; i < W * H; i++) {
        assert_true(back[i] == b[i] || (isinf(back[i]) && isinf(b[i])));
    }
    assert_int_equal(sta_exr_write("/nonexistent/dir/x.exr", channels, 2, W, H, &err), STA_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/dir/x.exr"));
    free(a);
    free(b);
    free(back);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(png_round_trip),
    cmocka_unit_test(exr_round_trip),
};

STA_TEST_MAIN(tests)
