/* SPDX-License-Identifier: MIT
 * LOD cut selection. */
#include "stream/select.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"

// Box outside a plane when its most positive corner is below it.
static int box_outside(const double plane[4], const double min[3], const double max[3])
{
    double x = plane[0] >= 0 ? max[0] : min[0];
    double y = plane[1] >= 0 ? max[1] : min[1];
    double z = plane[2] >= 0 ? max[2] : min[2];
    return plane[0] * x + plane[1] * y + plane[2] * z + plane[3] < 0;
}

double sta_select_node_priority(const sta_lod_node *node, const sta_camera *camera,
                                const sta_frustum *frustum)
{
    // Near and the four sides (plane 1, the far plane, is not used: the far plane
    // is at infinity).
    static const int used[5] = { 0, 2, 3, 4, 5 };
    for (int i = 0; i < 5; i++) {
        if (box_outside(frustum->planes[used[i]], node->min, node->max)) {
            return 0.0;
        }
    }
    // Distance from the eye to the box (0 inside).
    double d2 = 0.0;
    for (int a = 0; a < 3; a++) {
        double p = camera->position[a];
        double e = p < node->min[a] ? node->min[a] - p : (p > node->max[a] ? p - node->max[a] : 0);
        d2 += e * e;
    }
    double priority = node->spacing * sta_camera_pixels_per_metre(camera, sqrt(d2));
    return priority > 0 ? priority : 1e-12; // visible nodes always rank above culled
}

// A node's priority, 0 when the clip rejects it (nor can its children pass: their
// boxes lie inside its box, their levels are deeper, their spacing smaller).
typedef struct views {
    const sta_camera *cameras[1 + STA_SELECT_MAX_EXTRA_VIEWS];
    sta_frustum frusta[1 + STA_SELECT_MAX_EXTRA_VIEWS];
    size_t count;
} views;

static double clipped_priority(const sta_lod_node *node, const views *v, const sta_clip *clip)
{
    if (clip && !sta_clip_keeps_node(clip, node->level, node->spacing, node->min, node->max)) {
        return 0.0;
    }
    double best = 0.0;
    for (size_t i = 0; i < v->count; i++) {
        double p = sta_select_node_priority(node, v->cameras[i], &v->frusta[i]);
        best = p > best ? p : best;
    }
    return best;
}

static sta_status reserve(uint32_t **nodes, double **keys, size_t *capacity, size_t needed,
                          sta_error *err)
{
    // Both arrays share one capacity, which grows only when both have grown.
    size_t node_capacity = *capacity, key_capacity = *capacity;
    if (sta_array_reserve((void **)nodes, &node_capacity, needed, sizeof(**nodes), 256, NULL) !=
            STA_OK ||
        sta_array_reserve((void **)keys, &key_capacity, needed, sizeof(**keys), 256, NULL) !=
            STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory selecting nodes");
    }
    *capacity = node_capacity;
    return STA_OK;
}

static void heap_push(sta_selection *s, uint32_t node, double key)
{
    size_t i = s->heap_count++;
    while (i > 0) {
        size_t parent = (i - 1) / 2;
        if (s->heap_keys[parent] >= key) {
            break;
        }
        s->heap_keys[i] = s->heap_keys[parent];
        s->heap_nodes[i] = s->heap_nodes[parent];
        i = parent;
    }
    s->heap_keys[i] = key;
    s->heap_nodes[i] = node;
}

static void heap_pop(sta_selection *s, uint32_t *node, double *key)
{
    *node = s->heap_nodes[0];
    *key = s->heap_keys[0];
    size_t n = --s->heap_count;
    double last_key = s->heap_keys[n];
    uint32_t last_node = s->heap_nodes[n];
    size_t i = 0;
    for (;;) {
        size_t child = 2 * i + 1;
        if (child >= n) {
            break;
        }
        if (child + 1 < n && s->heap_keys[child + 1] > s->heap_keys[child]) {
            child++;
        }
        if (s->heap_keys[child] <= last_key) {
            break;
        }
        s->heap_keys[i] = s->heap_keys[child];
        s->heap_nodes[i] = s->heap_nodes[child];
        i = child;
    }
    if (n > 0) {
        s->heap_keys[i] = last_key;
        s->heap_nodes[i] = last_node;
    }
}

void sta_select_params_defaults(sta_select_params *p)
{
    p->budget_points = p->budget_points ? p->budget_points : STA_DEFAULT_BUDGET_POINTS;
    p->min_spacing_px = p->min_spacing_px > 0 ? p->min_spacing_px : STA_DEFAULT_MIN_SPACING_PX;
}

sta_status sta_select(const sta_lod_tree *tree, const sta_camera *camera,
                      const sta_select_params *params, sta_selection *s, sta_error *err)
{
    sta_select_params resolved = { 0 };
    if (params) {
        resolved = *params;
    }
    sta_select_params_defaults(&resolved);
    const uint64_t budget = resolved.budget_points;
    const double min_px = resolved.min_spacing_px;
    s->count = 0;
    s->point_count = 0;
    s->heap_count = 0;
    if (tree->count == 0) {
        return STA_OK;
    }
    views v = { .cameras = { camera }, .count = 1 };
    sta_camera_frustum(camera, 1e300, &v.frusta[0]);
    for (size_t i = 0; i < resolved.extra_view_count && i < STA_SELECT_MAX_EXTRA_VIEWS; i++) {
        v.cameras[v.count] = &resolved.extra_views[i];
        sta_camera_frustum(&resolved.extra_views[i], 1e300, &v.frusta[v.count]);
        v.count++;
    }
    sta_status status = reserve(&s->heap_nodes, &s->heap_keys, &s->heap_capacity, 8, err);
    if (status != STA_OK) {
        return status;
    }
    double root = clipped_priority(&tree->nodes[0], &v, resolved.clip);
    if (root > 0) {
        heap_push(s, 0, root);
    }
    while (s->heap_count > 0) {
        uint32_t index;
        double key;
        heap_pop(s, &index, &key);
        const sta_lod_node *node = &tree->nodes[index];
        if (s->point_count + node->point_count > budget) {
            continue; // its subtree waits for a better view or a bigger budget
        }
        status = reserve(&s->nodes, &s->priority, &s->capacity, s->count + 1, err);
        if (status != STA_OK) {
            return status;
        }
        s->nodes[s->count] = index;
        s->priority[s->count] = key;
        s->count++;
        s->point_count += node->point_count;
        if (key <= min_px || node->child_mask == 0) {
            continue;
        }
        status = reserve(&s->heap_nodes, &s->heap_keys, &s->heap_capacity, s->heap_count + 8, err);
        if (status != STA_OK) {
            return status;
        }
        uint32_t child = node->first_child;
        for (int slot = 0; slot < 8; slot++) {
            if (!(node->child_mask & (1u << slot))) {
                continue;
            }
            if (child < tree->count) {
                double p = clipped_priority(&tree->nodes[child], &v, resolved.clip);
                if (p > 0) {
                    heap_push(s, child, p);
                }
            }
            child++;
        }
    }
    return STA_OK;
}

void sta_selection_release(sta_selection *s)
{
    sta_free(s->nodes);
    sta_free(s->priority);
    sta_free(s->heap_nodes);
    sta_free(s->heap_keys);
    memset(s, 0, sizeof(*s));
}
