/* SPDX-License-Identifier: MIT
 * Clip box, polygon, class and return filters: node and point predicates, parsers. */
#include "stream/clip.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"

bool sta_clip_is_empty(const sta_clip *clip)
{
    return !sta_clip_filters_points(clip) && !clip->has_max_level && !(clip->min_spacing > 0.0);
}

bool sta_clip_filters_points(const sta_clip *clip)
{
    return clip->has_box || clip->polygon || clip->has_classes || clip->return_mask != 0;
}

void sta_clip_set_class(sta_clip *clip, unsigned c, bool keep)
{
    clip->has_classes = true;
    uint8_t bit = (uint8_t)(1u << (c % 8u));
    if (keep) {
        clip->class_mask[(c / 8u) % 32u] |= bit;
    } else {
        clip->class_mask[(c / 8u) % 32u] &= (uint8_t)~bit;
    }
}

bool sta_clip_keeps_class(const sta_clip *clip, unsigned c)
{
    return !clip->has_classes || (c < 256u && (clip->class_mask[c / 8u] >> (c % 8u)) & 1u);
}

bool sta_clip_point_in_polygon(const double *polygon, size_t count, double x, double y)
{
    bool inside = false;
    for (size_t i = 0, j = count - 1; i < count; j = i++) {
        double xi = polygon[2 * i], yi = polygon[2 * i + 1];
        double xj = polygon[2 * j], yj = polygon[2 * j + 1];
        if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) {
            inside = !inside;
        }
    }
    return inside;
}

// Whether segment a-b meets the rectangle [lo, hi] (Liang-Barsky clipping).
static bool segment_meets_rect(const double a[2], const double b[2], const double lo[2],
                               const double hi[2])
{
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 2; k++) {
        double d = b[k] - a[k];
        double p[2] = { -d, d };
        double q[2] = { a[k] - lo[k], hi[k] - a[k] };
        for (int s = 0; s < 2; s++) {
            if (p[s] == 0.0) {
                if (q[s] < 0.0) {
                    return false;
                }
            } else {
                double t = q[s] / p[s];
                if (p[s] < 0.0) {
                    t0 = t > t0 ? t : t0;
                } else {
                    t1 = t < t1 ? t : t1;
                }
            }
        }
    }
    return t0 <= t1;
}

// A rectangle meets a polygon when an edge crosses it or, with no edge crossing, when
// the rectangle lies inside (then any of its points is inside).
static bool polygon_meets_rect(const double *polygon, size_t count, const double lo[2],
                               const double hi[2])
{
    for (size_t i = 0, j = count - 1; i < count; j = i++) {
        if (segment_meets_rect(&polygon[2 * j], &polygon[2 * i], lo, hi)) {
            return true;
        }
    }
    return sta_clip_point_in_polygon(polygon, count, lo[0], lo[1]);
}

bool sta_clip_keeps_node(const sta_clip *clip, unsigned level, double spacing, const double min[3],
                         const double max[3])
{
    if (clip->has_max_level && level > clip->max_level) {
        return false;
    }
    if (clip->min_spacing > 0.0 && spacing < clip->min_spacing) {
        return false;
    }
    if (clip->has_box) {
        for (int a = 0; a < 3; a++) {
            if (max[a] < clip->box_min[a] || min[a] > clip->box_max[a]) {
                return false;
            }
        }
    }
    if (clip->polygon && !polygon_meets_rect(clip->polygon, clip->polygon_count, min, max)) {
        return false;
    }
    return true;
}

static bool keeps_returns(uint32_t mask, const sta_point *p)
{
    if (p->return_number >= 1 && p->return_number <= 15 && (mask >> p->return_number) & 1u) {
        return true;
    }
    if ((mask & STA_CLIP_RETURN_FIRST) && p->return_number == 1) {
        return true;
    }
    if ((mask & STA_CLIP_RETURN_LAST) && p->return_number == p->number_of_returns) {
        return true;
    }
    return (mask & STA_CLIP_RETURN_SINGLE) && p->number_of_returns == 1;
}

bool sta_clip_keeps_point(const sta_clip *clip, const sta_grid *grid, uint32_t attributes,
                          const sta_point *p)
{
    if (clip->has_classes && (!(attributes & STA_ATTR_CLASSIFICATION) ||
                              !sta_clip_keeps_class(clip, p->classification))) {
        return false;
    }
    if (clip->return_mask != 0 &&
        (!(attributes & STA_ATTR_RETURNS) || !keeps_returns(clip->return_mask, p))) {
        return false;
    }
    const int32_t xyz[3] = { p->X, p->Y, p->Z };
    double real[3];
    for (int a = 0; a < 3; a++) {
        real[a] = sta_grid_apply(grid, a, xyz[a]);
    }
    if (clip->has_box) {
        for (int a = 0; a < 3; a++) {
            if (real[a] < clip->box_min[a] || real[a] > clip->box_max[a]) {
                return false;
            }
        }
    }
    if (clip->polygon &&
        !sta_clip_point_in_polygon(clip->polygon, clip->polygon_count, real[0], real[1])) {
        return false;
    }
    return true;
}

// Reads an unsigned whole number at *s (advancing it); false when there is none.
static bool read_uint(const char **s, unsigned long max, unsigned long *out)
{
    if (!isdigit((unsigned char)**s)) {
        return false;
    }
    char *end = NULL;
    errno = 0;
    unsigned long v = strtoul(*s, &end, 10);
    if (errno || v > max) {
        return false;
    }
    *s = end;
    *out = v;
    return true;
}

sta_status sta_clip_parse_classes(sta_clip *clip, const char *text, sta_error *err)
{
    sta_clip parsed = *clip;
    memset(parsed.class_mask, 0, sizeof(parsed.class_mask));
    const char *s = text;
    for (;;) {
        unsigned long lo = 0, hi = 0;
        if (!read_uint(&s, 255, &lo)) {
            return sta_fail(err, STA_ERR_ARG,
                            "classes \"%s\": expected class numbers 0..255 or ranges (2,6,9-12)",
                            text);
        }
        hi = lo;
        if (*s == '-') {
            s++;
            if (!read_uint(&s, 255, &hi) || hi < lo) {
                return sta_fail(err, STA_ERR_ARG, "classes \"%s\": bad range after %lu", text, lo);
            }
        }
        for (unsigned long c = lo; c <= hi; c++) {
            sta_clip_set_class(&parsed, (unsigned)c, true);
        }
        if (*s != ',') {
            break;
        }
        s++;
    }
    if (*s != '\0') {
        return sta_fail(err, STA_ERR_ARG, "classes \"%s\": unexpected \"%s\"", text, s);
    }
    *clip = parsed;
    return STA_OK;
}

sta_status sta_clip_parse_returns(sta_clip *clip, const char *text, sta_error *err)
{
    static const struct {
        const char *name;
        uint32_t bit;
    } names[] = { { "first", STA_CLIP_RETURN_FIRST },
                  { "last", STA_CLIP_RETURN_LAST },
                  { "single", STA_CLIP_RETURN_SINGLE } };
    uint32_t mask = 0;
    const char *s = text;
    for (;;) {
        size_t n = strcspn(s, ",");
        unsigned long number = 0;
        const char *digits = s;
        bool known = false;
        if (read_uint(&digits, 15, &number) && digits == s + n && number >= 1) {
            mask |= 1u << number;
            known = true;
        }
        for (size_t i = 0; i < sizeof(names) / sizeof(names[0]) && !known; i++) {
            if (strlen(names[i].name) == n && strncmp(s, names[i].name, n) == 0) {
                mask |= names[i].bit;
                known = true;
            }
        }
        if (!known) {
            return sta_fail(err, STA_ERR_ARG,
                            "returns \"%s\": \"%.*s\" is not first, last, single or 1..15", text,
                            (int)n, s);
        }
        if (s[n] == '\0') {
            break;
        }
        s += n + 1;
    }
    clip->return_mask = mask;
    return STA_OK;
}

sta_status sta_clip_parse_box(sta_clip *clip, const char *text, sta_error *err)
{
    double v[6];
    const char *s = text;
    for (int i = 0; i < 6; i++) {
        char *end = NULL;
        errno = 0;
        v[i] = strtod(s, &end);
        bool sep_ok = i < 5 ? *end == ',' : *end == '\0';
        if (end == s || errno || !isfinite(v[i]) || !sep_ok) {
            return sta_fail(err, STA_ERR_ARG,
                            "box \"%s\": expected six numbers XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX", text);
        }
        s = end + 1;
    }
    for (int a = 0; a < 3; a++) {
        if (v[a] > v[a + 3]) {
            return sta_fail(err, STA_ERR_ARG, "box \"%s\": minimum %g above maximum %g on axis %c",
                            text, v[a], v[a + 3], "xyz"[a]);
        }
    }
    clip->has_box = true;
    memcpy(clip->box_min, v, sizeof(clip->box_min));
    memcpy(clip->box_max, v + 3, sizeof(clip->box_max));
    return STA_OK;
}

sta_status sta_clip_read_polygon(const char *path, double **out_xy, size_t *out_count,
                                 sta_error *err)
{
    *out_xy = NULL;
    *out_count = 0;
    FILE *f = fopen(path, "r");
    if (!f) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot open polygon: %s", path, strerror(errno));
    }
    double *xy = NULL;
    size_t count = 0, capacity = 0;
    char line[512];
    unsigned line_number = 0;
    sta_status status = STA_OK;
    while (status == STA_OK && fgets(line, sizeof(line), f)) {
        line_number++;
        const char *s = line;
        while (isspace((unsigned char)*s)) {
            s++;
        }
        if (*s == '\0' || *s == '#') {
            continue;
        }
        char *end = NULL;
        double x = strtod(s, &end);
        const char *t = end;
        while (*t == ' ' || *t == '\t' || *t == ',') {
            t++;
        }
        double y = end != s ? strtod(t, &end) : 0.0;
        while (end && isspace((unsigned char)*end)) {
            end++;
        }
        if (end == t || !end || *end != '\0' || !isfinite(x) || !isfinite(y)) {
            status = sta_fail(err, STA_ERR_FORMAT, "%s: line %u: expected \"x y\", got \"%.40s\"",
                              path, line_number, s);
        } else if (sta_array_reserve((void **)&xy, &capacity, 2 * (count + 1), sizeof(*xy), 64,
                                     err) != STA_OK) {
            status = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
        } else {
            xy[2 * count] = x;
            xy[2 * count + 1] = y;
            count++;
        }
    }
    if (status == STA_OK && ferror(f)) {
        status = sta_fail(err, STA_ERR_IO, "%s: read failed", path);
    }
    if (status == STA_OK && count < 3) {
        status = sta_fail(err, STA_ERR_FORMAT, "%s: a polygon needs 3 vertices or more, found %zu",
                          path, count);
    }
    fclose(f);
    if (status != STA_OK) {
        sta_free(xy);
        return status;
    }
    *out_xy = xy;
    *out_count = count;
    return STA_OK;
}
