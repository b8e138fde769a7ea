/* SPDX-License-Identifier: MIT
 * Fuzz target for the OBJ mesh loader: any bytes must give an error status or a
 * consistent mesh, never a crash. Checked invariants (a violation traps): every
 * triangle index is below the vertex count; every coordinate is finite; a failed load
 * leaves the mesh zeroed.
 */
#include <math.h>
#include <stdint.h>

#include "io/obj.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sta_mesh mesh;
    sta_error err = { 0 };
    if (sta_obj_load_mesh_memory(data, size, "fuzz.obj", &mesh, &err) != STA_OK) {
        if (mesh.positions || mesh.triangles || mesh.vertex_count || mesh.triangle_count) {
            __builtin_trap();
        }
        return 0;
    }
    for (size_t i = 0; i < 3 * mesh.triangle_count; i++) {
        if (mesh.triangles[i] >= mesh.vertex_count) {
            __builtin_trap();
        }
    }
    for (size_t i = 0; i < 3 * mesh.vertex_count; i++) {
        if (!isfinite(mesh.positions[i])) {
            __builtin_trap();
        }
    }
    sta_mesh_release(&mesh);
    return 0;
}
