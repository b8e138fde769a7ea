// SPDX-License-Identifier: MIT
// The sparse HPR operator's copy step (docs/HPR.md, "Sparse operator"): after the
// pyramidal operator ran on the even (x, y) anchors only, each other pixel copies its
// up to 4 nearest anchors' label when they all agree, the label is of its kind (point
// or empty) and, for a point, every anchor's depth is within STA_HPR_SPARSE_DEPTH_TAU of its own
// (no depth edge); otherwise it goes on the list the operator refines. Twin:
// sta_hpr_ref_sparse_labels (src/render/ref/hpr_sparse_ref.c).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_HPR_SPARSE_CLASSIFY_SAMPLER_POSITION) uniform sampler2D u_position;
layout(binding = STA_HPR_SPARSE_CLASSIFY_IMAGE_LABEL, r32f) uniform image2D u_label;
layout(std430, binding = STA_HPR_SPARSE_CLASSIFY_BUFFER_LIST) buffer RefineList
{
    uint u_count;
    uint u_pixels[]; // x | y << 16
};
// The refinement's indirect dispatch (x, y, z workgroups): y grows here with the list,
// so that no count has to be read back on the CPU to size it.
layout(std430, binding = STA_HPR_SPARSE_CLASSIFY_BUFFER_DISPATCH) buffer RefineDispatch
{
    uint u_groups[3];
};
uniform ivec2 u_size;

// The workgroup's listed pixels: counted in shared memory, then one atomic on the
// global count per workgroup (the global count is one cache line that every listed
// pixel's atomic would contend for).
shared uint s_listed;
shared uint s_base;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (gl_LocalInvocationIndex == 0u) {
        s_listed = 0u;
    }
    barrier();
    // Anchors (even x and y) and pixels outside the view take part in the barriers only.
    bool listed = false;
    if (p.x < u_size.x && p.y < u_size.y && ((p.x | p.y) & 1) != 0) {
        ivec2 a0 = p & ~1;
        ivec2 a1 = min(a0 + 2 * (p & 1), (u_size - 1) & ~1);
        ivec2 anchors[4] = ivec2[4](a0, ivec2(a1.x, a0.y), ivec2(a0.x, a1.y), a1);
        float l0 = imageLoad(u_label, a0).x;
        vec4 own = texelFetch(u_position, p, 0);
        bool own_point = own.w > 0.5;
        bool ok = own_point == (l0 == STA_LABEL_VISIBLE || l0 == STA_LABEL_HIDDEN);
        precise float zp = -own.z;
        precise float tau = STA_HPR_SPARSE_DEPTH_TAU * zp;
        for (int i = 1; i < 4 && ok; i++) {
            ok = imageLoad(u_label, anchors[i]).x == l0;
        }
        for (int i = 0; i < 4 && ok && own_point; i++) {
            precise float d = abs(-texelFetch(u_position, anchors[i], 0).z - zp);
            ok = d <= tau;
        }
        if (ok) {
            imageStore(u_label, p, vec4(l0, 0.0, 0.0, 0.0));
        }
        listed = !ok;
    }
    uint local = 0u;
    if (listed) {
        local = atomicAdd(s_listed, 1u);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && s_listed != 0u) {
        s_base = atomicAdd(u_count, s_listed);
    }
    barrier();
    if (listed) {
        uint k = s_base + local;
        u_pixels[k] = uint(p.x) | (uint(p.y) << 16);
        // The entries are 0..count-1 without gaps, so the first entry of each dispatch
        // row alone raises the row count: one atomic per row, not per pixel.
        const uint row = uint(STA_HPR_LIST_WIDTH * STA_WORKGROUP_SIZE_Y);
        if (k % row == 0u) {
            atomicMax(u_groups[1], k / row + 1u);
        }
    }
}
