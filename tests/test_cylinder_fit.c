/* SPDX-License-Identifier: MIT
 * Tests for the cylinder of an elongated set from its moment tensors
 * (preprocess/cylinder_fit.c) against analytic truth: the front of a pole gets its axis,
 * radius and exact radial normals; with range noise the normal where the point's ray enters
 * the cylinder is nearer the truth than the radial one at the noisy point; a tilted pole
 * too; a plane strip, a line, too few points, no points and sums that may have overflowed
 * are refused, a point on the axis has no normal, never NaN. */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "cylinder_fit.h"

#define PI 3.14159265358979323846

enum {
    ROWS = 40,
    ACROSS = 30,
    POINTS = ROWS * ACROSS
};

// Degrees between two unit vectors, unoriented.
static double degrees(const double a[3], const double b[3])
{
    double c = fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
    return acos(c > 1.0 ? 1.0 : c) * 180.0 / PI;
}

// A pole of radius 110 units along `axis` (unit; its foot at `foot`, 12 units a row), its
// front 150 degrees towards `front` (unit, across the axis); each point moved by `noise`
// times a pseudo-random number in [-1, 1] along its ray from `scanner` (grid units), its
// radial truth in truth[i]. Returns the sums (offsets from the origin) and fills d.
static sta_tensor_sums pole(const double foot[3], const double axis[3], const double front[3],
                            const double scanner[3], double noise, int64_t (*d)[3],
                            double (*truth)[3])
{
    double side[3] = { axis[1] * front[2] - axis[2] * front[1],
                       axis[2] * front[0] - axis[0] * front[2],
                       axis[0] * front[1] - axis[1] * front[0] };
    sta_tensor_sums sums;
    memset(&sums, 0, sizeof(sums));
    uint64_t seed = 12;
    for (int r = 0, i = 0; r < ROWS; r++) {
        for (int k = 0; k < ACROSS; k++, i++) {
            double phi = (-75.0 + 150.0 * (double)k / (ACROSS - 1)) * PI / 180.0, p[3], ray[3];
            double len = 0.0, shift = noise * (2.0 * (double)sta_test_frand(&seed) - 1.0);
            for (int a = 0; a < 3; a++) {
                truth[i][a] = cos(phi) * front[a] + sin(phi) * side[a];
                p[a] = foot[a] + 12.0 * r * axis[a] + 110.0 * truth[i][a];
                ray[a] = p[a] - scanner[a];
                len += ray[a] * ray[a];
            }
            uint64_t u[3];
            for (int a = 0; a < 3; a++) {
                d[i][a] = (int64_t)llround(p[a] + shift * ray[a] / sqrt(len));
                u[a] = (uint64_t)d[i][a];
            }
            sta_tensor_sums_add(&sums, u);
        }
    }
    return sums;
}

// Without noise: the axis, the radius, radial normals everywhere (the grid's rounding the
// only error), each point on the cylinder.
static void pole_front_gets_radial_normals(void **state)
{
    (void)state;
    static int64_t d[POINTS][3];
    static double truth[POINTS][3];
    const double foot[3] = { 300, 300, 20 }, axis[3] = { 0, 0, 1 }, front[3] = { 1, 0, 0 };
    const double scanner[3] = { 5000, 300, 1500 };
    sta_tensor_sums sums = pole(foot, axis, front, scanner, 0.0, d, truth);
    sta_cylinder c;
    assert_true(sta_cylinder_fit(&sums, 1024.0, &c));
    assert_true(degrees(c.axis, axis) < 0.01);
    assert_true(c.elongation > 3.0);
    assert_true(fabs(c.radius * c.spread - 110.0) < 1.0);
    assert_true(sqrt(c.residual) * c.spread < 1.0); // (rounding to the grid: under a unit)
    double worst = 0.0;
    for (int i = 0; i < POINTS; i++) {
        double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] }, n[3], off;
        assert_true(sta_cylinder_normal(&c, p, n, &off));
        assert_true(off < 0.01);
        worst = fmax(worst, degrees(n, truth[i]));
        assert_true(sta_cylinder_normal_seen(&c, p, scanner, n, &off));
        worst = fmax(worst, degrees(n, truth[i]));
    }
    print_message("pole front: radius %.2f, worst normal %.3f degrees\n", c.radius * c.spread,
                  worst);
    assert_true(worst < 1.0); // (0.68: half a unit of rounding is 0.26 degrees at 110)
}

// Range noise of +-15 units (the street's poles: 15 mm on 110): the fit still finds the
// pole; the radial normal at a noisy point turns with the noise's share across the ray, the
// normal where the ray enters the cylinder does not.
static void noisy_pole_is_seen_along_its_rays(void **state)
{
    (void)state;
    static int64_t d[POINTS][3];
    static double truth[POINTS][3];
    const double foot[3] = { 300, 300, 20 }, axis[3] = { 0, 0, 1 }, front[3] = { 1, 0, 0 };
    const double scanner[3] = { 3000, 800, 1500 };
    sta_tensor_sums sums = pole(foot, axis, front, scanner, 15.0, d, truth);
    sta_cylinder c;
    assert_true(sta_cylinder_fit(&sums, 1024.0, &c));
    assert_true(fabs(c.radius * c.spread - 110.0) < 5.0);
    assert_true(sqrt(c.residual) < 0.15 * c.radius); // (the converter's bound)
    double radial = 0.0, seen = 0.0;
    for (int i = 0; i < POINTS; i++) {
        double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] }, n[3], off;
        assert_true(sta_cylinder_normal(&c, p, n, &off));
        radial += degrees(n, truth[i]) / POINTS;
        assert_true(sta_cylinder_normal_seen(&c, p, scanner, n, &off));
        assert_true(isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2]));
        seen += degrees(n, truth[i]) / POINTS;
    }
    print_message("noisy pole: radius %.1f, mean error radial %.2f, along the rays %.2f\n",
                  c.radius * c.spread, radial, seen);
    assert_true(seen < 0.7 * radial); // (2.33 and 1.27 degrees)
    assert_true(seen < 2.0);
}

// A pole tilted by 30 degrees: the axis and the normals follow it.
static void tilted_pole_gets_its_axis(void **state)
{
    (void)state;
    static int64_t d[POINTS][3];
    static double truth[POINTS][3];
    const double s = sin(30.0 * PI / 180.0), k = cos(30.0 * PI / 180.0);
    const double foot[3] = { 300, 300, 200 }, axis[3] = { s, 0, k }, front[3] = { k, 0, -s };
    const double scanner[3] = { 5000, 300, 1500 };
    sta_tensor_sums sums = pole(foot, axis, front, scanner, 0.0, d, truth);
    sta_cylinder c;
    assert_true(sta_cylinder_fit(&sums, 1024.0, &c));
    assert_true(degrees(c.axis, axis) < 0.05);
    double worst = 0.0;
    for (int i = 0; i < POINTS; i++) {
        double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] }, n[3], off;
        assert_true(sta_cylinder_normal(&c, p, n, &off));
        worst = fmax(worst, degrees(n, truth[i]));
    }
    assert_true(worst < 0.5);
}

// What cannot hold a cylinder is refused: a plane strip (its cross-section a line), a
// line, too few points, no points, sums that may have overflowed; a point on the axis has
// no normal.
static void degenerate_sets_are_refused(void **state)
{
    (void)state;
    sta_tensor_sums strip, line, few, none;
    memset(&strip, 0, sizeof(strip));
    memset(&line, 0, sizeof(line));
    memset(&few, 0, sizeof(few));
    memset(&none, 0, sizeof(none));
    for (uint64_t z = 0; z < 40; z++) {
        for (uint64_t x = 0; x < 10; x++) {
            const uint64_t p[3] = { 100 + 20 * x, 300, 12 * z }; // the plane y = 300
            sta_tensor_sums_add(&strip, p);
        }
        const uint64_t q[3] = { 100, 100, 12 * z };
        sta_tensor_sums_add(&line, q);
        if (z < 9) {
            const uint64_t r[3] = { 100 + (z % 3) * 50, 100 + (z / 3) * 50, 40 * z };
            sta_tensor_sums_add(&few, r);
        }
    }
    sta_cylinder c;
    assert_false(sta_cylinder_fit(&strip, 1024.0, &c));
    assert_false(sta_cylinder_fit(&line, 1024.0, &c));
    assert_false(sta_cylinder_fit(&few, 1024.0, &c));
    assert_false(sta_cylinder_fit(&none, 1024.0, &c));
    // The pole's sums, as if its offsets could reach 2^16 units: n extent^4 over 2^62.
    static int64_t d[POINTS][3];
    static double truth[POINTS][3];
    const double foot[3] = { 300, 300, 20 }, axis[3] = { 0, 0, 1 }, front[3] = { 1, 0, 0 };
    const double scanner[3] = { 5000, 300, 1500 };
    sta_tensor_sums sums = pole(foot, axis, front, scanner, 0.0, d, truth);
    assert_false(sta_cylinder_fit(&sums, 65536.0, &c));
    assert_true(sta_cylinder_fit(&sums, 1024.0, &c));
    double centre[3], n[3] = { 7, 7, 7 }, off;
    for (int a = 0; a < 3; a++) {
        centre[a] = c.mean[a] + c.spread * (c.centre[0] * c.e[0][a] + c.centre[1] * c.e[1][a]);
    }
    assert_false(sta_cylinder_normal(&c, centre, n, &off));
    assert_false(sta_cylinder_normal_seen(&c, centre, scanner, n, &off));
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(pole_front_gets_radial_normals),
    cmocka_unit_test(noisy_pole_is_seen_along_its_rays),
    cmocka_unit_test(tilted_pole_gets_its_axis),
    cmocka_unit_test(degenerate_sets_are_refused),
};

STA_TEST_MAIN(tests)
