/* SPDX-License-Identifier: MIT
 * Fuzz target for the PLY reader and mesh loader: any bytes must give an error status
 * or consistent results, never a crash. Checked invariants (a violation traps):
 * - reads yield exactly point_count points, batch indices run in order;
 * - every coordinate lies within the grid's +-2^30 (plus rounding);
 * - a seek to a point gives the same point as the sequential read;
 * - every mesh triangle index is below the vertex count.
 * A file that fails to open is opened again with salvage_truncated. Inputs that do
 * not start with "ply" are left to the other targets (format detection is cloud.c's).
 */
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "io/cloud.h"
#include "io/ply.h"

#define BATCH_CAPACITY 64

static bool same_point(const sta_point *a, const sta_point *b)
{
    return a->X == b->X && a->Y == b->Y && a->Z == b->Z && a->red == b->red &&
           a->green == b->green && a->blue == b->blue && a->intensity == b->intensity &&
           memcmp(a->normal, b->normal, sizeof(a->normal)) == 0;
}

static bool within_grid(int32_t v)
{
    return v >= -(1 << 30) - 1 && v <= (1 << 30) + 1;
}

static void read_and_seek(sta_cloud_reader *reader)
{
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    sta_point_batch batch = { 0 };
    if (sta_point_batch_init(&batch, BATCH_CAPACITY, info->extra_size, NULL) != STA_OK) {
        return;
    }
    uint64_t mid = info->point_count / 2;
    sta_point at_mid = { 0 };
    uint64_t total = 0;
    for (;;) {
        if (sta_cloud_read(reader, &batch, NULL) != STA_OK) {
            __builtin_trap(); // every vertex was validated at open
        }
        if (batch.count == 0) {
            break;
        }
        if (batch.first_index != total) {
            __builtin_trap();
        }
        for (size_t i = 0; i < batch.count; i++) {
            const sta_point *p = &batch.points[i];
            if (!within_grid(p->X) || !within_grid(p->Y) || !within_grid(p->Z)) {
                __builtin_trap();
            }
            if (total + i == mid) {
                at_mid = *p;
            }
        }
        total += batch.count;
    }
    if (total != info->point_count) {
        __builtin_trap();
    }
    if (info->point_count > 0) {
        if (sta_cloud_seek(reader, mid, NULL) != STA_OK ||
            sta_cloud_read(reader, &batch, NULL) != STA_OK || batch.count == 0 ||
            batch.first_index != mid || !same_point(&batch.points[0], &at_mid)) {
            __builtin_trap();
        }
    }
    if (sta_cloud_seek(reader, info->point_count, NULL) != STA_OK ||
        sta_cloud_read(reader, &batch, NULL) != STA_OK || batch.count != 0) {
        __builtin_trap();
    }
    sta_point_batch_release(&batch);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    // Stay on PLY: inputs mutated into another format's signature belong to its target.
    if (size >= 4 && memcmp(data, "ply", 3) != 0) {
        return 0;
    }
    for (int salvage = 0; salvage < 2; salvage++) {
        const sta_read_options options = { .salvage_truncated = salvage == 1 };
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        if (sta_cloud_open_memory(data, size, "fuzz.ply", &options, &reader, &err) == STA_OK) {
            read_and_seek(reader);
            sta_cloud_close(reader);
            break;
        }
        if (err.message[0] == '\0' || memchr(err.message, '\0', sizeof(err.message)) == NULL) {
            __builtin_trap(); // a failure always says why
        }
    }

    sta_mesh mesh = { 0 };
    if (sta_ply_load_mesh_memory(data, size, "fuzz.ply", &mesh, NULL) == STA_OK) {
        for (size_t i = 0; i < mesh.triangle_count * 3; i++) {
            if (mesh.triangles[i] >= mesh.vertex_count) {
                __builtin_trap();
            }
        }
    } else if (mesh.positions || mesh.triangles || mesh.vertex_count) {
        __builtin_trap(); // a failed load leaves the mesh zeroed
    }
    sta_mesh_release(&mesh);
    return 0;
}
