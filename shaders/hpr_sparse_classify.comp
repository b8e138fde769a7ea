// SPDX-License-Identifier: MIT
// The sparse HPR operator's copy step (docs/HPR.md, "Sparse operator"), run with the
// strides u_stride = sta_hpr_anchor_stride / 2, ..., 2, 1 in turn. On the grid of pixels
// whose x and y are multiples of u_stride, the anchors (x and y multiples of 2 u_stride)
// are labelled (by the operator or the step before);
// each other pixel of the grid copies the label its nearest anchors of its own kind
// (point or empty) agree on, when there is at least one such anchor and, for a point,
// each of them lies within STA_HPR_SPARSE_DEPTH_TAU of its depth (no depth edge);
// otherwise it goes on the list the operator refines. Points of the coarse steps are
// always listed (the operator on every even point keeps each error of the full operator
// within 0.1 %; copying them from anchors 4 px apart did not, docs/BENCHMARKS.md).
// One invocation per tile of
// STA_HPR_CLASSIFY_TILE x STA_HPR_CLASSIFY_TILE 2x2 blocks of the grid, block by block:
// the block's anchor and its three other pixels, which share the anchors (x, y),
// (x + 2, y), (x, y + 2), (x + 2, y + 2) in grid steps. The tile's listed pixels go on
// the list together (one atomic), so the refinement's workgroups, which take the list's
// entries in order, get neighbouring pixels: with an invocation per block, the
// workgroups running at the same time interleaved their entries, and HPR took 4.5-10
// CPU ms more at 1080p on llvmpipe (docs/BENCHMARKS.md, issue 15, fourteenth round).
// Twin: sta_hpr_ref_sparse_labels (src/render/ref/hpr_sparse_ref.c).
// A workgroup is a row of tiles, so that the list takes whole rows of tiles in order.
layout(local_size_x = STA_HPR_CLASSIFY_GROUP_TILES, local_size_y = 1) in;
// imageLoad, not texelFetch: cheaper on llvmpipe (hpr_occlusion.comp)
layout(binding = STA_HPR_SPARSE_CLASSIFY_IMAGE_POSITION,
       rgba32f) readonly uniform image2D u_position;
layout(binding = STA_HPR_SPARSE_CLASSIFY_IMAGE_LABEL, r16f) uniform image2D u_label;
// Two lists in one buffer: points from the front, empty pixels from the back, each
// refined by a program of its own (hpr_occlusion.comp, HPR_EMPTY_LIST): a program for
// both kinds ran the other kind's code, masked, for every pixel of a mixed SIMD group.
layout(std430, binding = STA_HPR_SPARSE_CLASSIFY_BUFFER_LIST) buffer RefineList
{
    uint u_count;       // points listed
    uint u_empty_count; // empty pixels listed
    uint u_pixels[];    // x | y << 16
};
// The refinements' indirect dispatches (x, y, z workgroups; points', then empty
// pixels'): y grows here with each list, so that no count has to be read back on the
// CPU to size them.
layout(std430, binding = STA_HPR_SPARSE_CLASSIFY_BUFFER_DISPATCH) buffer RefineDispatch
{
    uint u_groups[6];
};
uniform ivec2 u_size;
uniform int u_stride; // pixels per grid step

// STA_HPR_CLASSIFY_TILE (pass_hpr.c): 2x2 blocks per tile side.
// The tile's listed pixels (x | y << 16, bit EMPTY_BIT set for an empty pixel: y < 2^15),
// at most 3 a block.
const uint EMPTY_BIT = 0x80000000u;
uint g_listed[3 * STA_HPR_CLASSIFY_TILE * STA_HPR_CLASSIFY_TILE];
uint g_count = 0u;
uint g_empty = 0u; // of them empty

bool is_point_label(float label)
{
    return label == STA_LABEL_VISIBLE || label == STA_LABEL_HIDDEN;
}

// Folds anchor (label la, depth da) into pixel p's copy: anchors of the other kind are
// left out; `count` of p's kind so far, their common `label`, `ok` while they agree
// and (for a point) lie within the depth tolerance `tau` of its depth `zp`.
void fold_anchor(float la, float da, bool own_point, float zp, float tau, inout int count,
                 inout float label, inout bool ok)
{
    if (is_point_label(la) != own_point) {
        return;
    }
    label = count == 0 ? la : label;
    precise float d = abs(da - zp);
    ok = ok && la == label && (!own_point || d <= tau);
    count++;
}

// Grid pixel g: copies the label of its anchors of its kind (2 or 4 of the block's: .x
// and .y of la / da always, .z and .w when `four`), or adds it to g_listed.
void classify(ivec2 g, ivec2 grid, bool four, vec4 la, vec4 da)
{
    if (g.x >= grid.x || g.y >= grid.y) {
        return;
    }
    ivec2 p = g * u_stride;
    vec4 own = imageLoad(u_position, p);
    bool own_point = own.w > 0.5;
    precise float zp = -own.z;
    precise float tau = STA_HPR_SPARSE_DEPTH_TAU * zp;
    int count = 0;
    float label = 0.0;
    bool ok = !(own_point && u_stride > 1); // the coarse pass lists every point
    fold_anchor(la.x, da.x, own_point, zp, tau, count, label, ok);
    fold_anchor(la.y, da.y, own_point, zp, tau, count, label, ok);
    if (four) {
        fold_anchor(la.z, da.z, own_point, zp, tau, count, label, ok);
        fold_anchor(la.w, da.w, own_point, zp, tau, count, label, ok);
    }
    if (ok && count > 0) {
        imageStore(u_label, p, vec4(label, 0.0, 0.0, 0.0));
        return;
    }
    g_listed[g_count] = uint(p.x) | (uint(p.y) << 16) | (own_point ? 0u : EMPTY_BIT);
    g_count++;
    g_empty += own_point ? 0u : 1u;
}

// The 2x2 block whose anchor is a0 (in grid steps).
void classify_block(ivec2 a0, ivec2 grid)
{
    // The 4 anchors, clamped to the grid's last even row and column (as the twin).
    ivec2 a1 = min(a0 + 2, (grid - 1) & ~1);
    ivec2 q0 = a0 * u_stride, q3 = a1 * u_stride;
    ivec2 q1 = ivec2(q3.x, q0.y), q2 = ivec2(q0.x, q3.y);
    vec4 la = vec4(imageLoad(u_label, q0).x, imageLoad(u_label, q1).x, imageLoad(u_label, q2).x,
                   imageLoad(u_label, q3).x);
    // Anchor depths matter only for point anchors (a point compares them with its
    // own): not fetched for the others (copy step at stride 1: 22 -> 20 CPU ms).
    vec4 da = vec4(0.0);
    if (is_point_label(la.x)) {
        da.x = -imageLoad(u_position, q0).z;
    }
    if (is_point_label(la.y)) {
        da.y = -imageLoad(u_position, q1).z;
    }
    if (is_point_label(la.z)) {
        da.z = -imageLoad(u_position, q2).z;
    }
    if (is_point_label(la.w)) {
        da.w = -imageLoad(u_position, q3).z;
    }
    // (x + 1, y): anchors 0 and 1; (x, y + 1): 0 and 2; (x + 1, y + 1): all four.
    classify(a0 + ivec2(1, 0), grid, false, la, da);
    classify(a0 + ivec2(0, 1), grid, false, la.xzyw, da.xzyw);
    classify(a0 + ivec2(1, 1), grid, true, la, da);
}

void main()
{
    ivec2 grid = (u_size + u_stride - 1) / u_stride; // the grid's size
    // The tile's first block anchor, in grid steps.
    ivec2 t0 = 2 * STA_HPR_CLASSIFY_TILE * ivec2(gl_GlobalInvocationID.xy);
    for (int by = 0; by < STA_HPR_CLASSIFY_TILE; by++) {
        for (int bx = 0; bx < STA_HPR_CLASSIFY_TILE; bx++) {
            ivec2 a0 = t0 + 2 * ivec2(bx, by);
            if (a0.x < grid.x && a0.y < grid.y) {
                classify_block(a0, grid);
            }
        }
    }
    if (g_count == 0u) {
        return;
    }
    uint points = g_count - g_empty;
    uint base = points > 0u ? atomicAdd(u_count, points) : 0u;
    uint empty_base = g_empty > 0u ? atomicAdd(u_empty_count, g_empty) : 0u;
    // The entries of each list are 0..count-1 without gaps, so the entry that opens a
    // dispatch row alone raises its row count: one atomic per row, not per pixel. Entry
    // k of the empty pixels' list lies at u_pixels[length - 1 - k].
    const uint row = uint(STA_HPR_LIST_WIDTH * STA_WORKGROUP_SIZE_Y);
    const uint last = uint(u_pixels.length()) - 1u;
    for (uint i = 0u; i < g_count; i++) {
        bool empty = (g_listed[i] & EMPTY_BIT) != 0u;
        uint k = empty ? empty_base : base;
        // Both indices as values first: NVIDIA's compiler (driver 580) fails to link a
        // select written inside these indices ("C9999: unexpected expression in
        // DUI_foreachId", docs/BENCHMARKS.md).
        uint at = empty ? last - k : k;
        int dispatch = empty ? 4 : 1;
        u_pixels[at] = g_listed[i] & ~EMPTY_BIT;
        if (k % row == 0u) {
            atomicMax(u_groups[dispatch], k / row + 1u);
        }
        empty_base += empty ? 1u : 0u;
        base += empty ? 0u : 1u;
    }
}
