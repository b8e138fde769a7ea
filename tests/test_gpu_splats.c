/* SPDX-License-Identifier: MIT
 * The splat attribute layout: octahedral normals round-trip within 0.01 degree over the
 * whole sphere (both hemispheres, the axes, the folding seams), degenerate normals get
 * +Z, and half-float radii keep 3 significant digits and clamp bad values. */
#include "test_support.h"

#include <math.h>

#include "stream/gpu_splats.h"

/* atan2 of |a x b| and a . b: exact near 0, where acos of a float dot product is not */
static double angle_deg(const float a[3], const float b[3])
{
    double ax = a[0], ay = a[1], az = a[2], bx = b[0], by = b[1], bz = b[2];
    double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    double dot = ax * bx + ay * by + az * bz;
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), dot) * 180.0 / M_PI;
}

static void octahedral_round_trip_over_the_sphere(void **state)
{
    (void)state;
    double worst = 0.0;
    /* a Fibonacci sphere plus the axes and the fold seams (z = 0, |x| = |y|) */
    for (int i = 0; i < 20000 + 14; i++) {
        float n[3];
        if (i < 20000) {
            double z = 1.0 - (2.0 * i + 1.0) / 20000.0, r = sqrt(1.0 - z * z);
            double phi = i * 2.399963229728653;
            n[0] = (float)(r * cos(phi)), n[1] = (float)(r * sin(phi)), n[2] = (float)z;
        } else {
            static const float special[14][3] = { { 1, 0, 0 },
                                                  { -1, 0, 0 },
                                                  { 0, 1, 0 },
                                                  { 0, -1, 0 },
                                                  { 0, 0, 1 },
                                                  { 0, 0, -1 },
                                                  { 0.7071f, 0.7071f, 0 },
                                                  { -0.7071f, 0.7071f, 0 },
                                                  { 0.5f, -0.5f, -0.7071f },
                                                  { -0.5f, -0.5f, -0.7071f },
                                                  { 0.6f, 0, -0.8f },
                                                  { 0, -0.6f, -0.8f },
                                                  { 0.01f, 0, -0.99995f },
                                                  { -0.01f, 0.01f, -0.9999f } };
            for (int a = 0; a < 3; a++) {
                n[a] = special[i - 20000][a];
            }
            float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            n[0] /= len, n[1] /= len, n[2] /= len;
        }
        uint16_t oct[2];
        float back[3];
        sta_octahedral_encode(n, oct);
        sta_octahedral_decode(oct, back);
        double e = angle_deg(n, back);
        worst = e > worst ? e : worst;
        float len = sqrtf(back[0] * back[0] + back[1] * back[1] + back[2] * back[2]);
        assert_true(fabsf(len - 1.0f) < 1e-5f);
    }
    assert_true(worst < 0.01);
}

static void degenerate_normals_encode_as_up(void **state)
{
    (void)state;
    const float bad[3][3] = { { 0, 0, 0 }, { NAN, 0, 1 }, { INFINITY, 1, 0 } };
    for (int i = 0; i < 3; i++) {
        uint16_t oct[2];
        float back[3];
        sta_octahedral_encode(bad[i], oct);
        sta_octahedral_decode(oct, back);
        assert_true(back[2] > 0.9999f);
    }
}

static void half_radius_round_trip_and_clamps(void **state)
{
    (void)state;
    const float values[] = { 0.001f, 0.0123f, 0.05f, 0.5f, 1.0f, 3.75f, 100.0f, 1234.5f };
    for (size_t i = 0; i < sizeof values / sizeof values[0]; i++) {
        float back = sta_half_to_float(sta_half_from_float(values[i]));
        assert_true(fabsf(back - values[i]) <= values[i] * (1.0f / 1024.0f));
    }
    assert_int_equal(sta_half_from_float(1.0f), 0x3c00); /* IEEE binary16 of 1 */
    assert_int_equal(sta_half_from_float(0.5f), 0x3800);
    assert_int_equal(sta_half_from_float(-2.0f), 0);
    assert_int_equal(sta_half_from_float(NAN), 0);
    assert_int_equal(sta_half_from_float(1e9f), 0x7bff);
    /* subnormals: 2^-24 is the smallest step */
    assert_true(fabsf(sta_half_to_float(sta_half_from_float(3e-6f)) - 3e-6f) < 6e-8f);
}

static void records_hold_normal_and_radius(void **state)
{
    (void)state;
    const float normals[2][3] = { { 0, 0, -1 }, { 0.6f, 0.8f, 0 } };
    const float radii[2] = { 0.02f, 7.5f };
    uint8_t records[2 * STA_GPU_SPLAT_SIZE];
    sta_gpu_splats_encode(normals, radii, 2, records);
    for (int i = 0; i < 2; i++) {
        float n[3], r;
        sta_gpu_splat_decode(records + i * STA_GPU_SPLAT_SIZE, n, &r);
        assert_true(angle_deg(n, normals[i]) < 0.01);
        assert_true(fabsf(r - radii[i]) <= radii[i] / 1024.0f);
        assert_int_equal(records[i * STA_GPU_SPLAT_SIZE + 6], 0);
        assert_int_equal(records[i * STA_GPU_SPLAT_SIZE + 7], 0);
    }
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(octahedral_round_trip_over_the_sphere),
    cmocka_unit_test(degenerate_normals_encode_as_up),
    cmocka_unit_test(half_radius_round_trip_and_clamps),
    cmocka_unit_test(records_hold_normal_and_radius),
};

STA_TEST_MAIN(tests)
