// SPDX-License-Identifier: MIT
// HPR point pyramid, one level: each texel keeps the point of least depth (d = -z)
// among the points (w > 0.5) of its 2x2 block of the level below, first in the order
// (0,0), (1,0), (0,1), (1,1) on a tie; texels outside the level below are ignored and
// a block with no point gives zeros. Twin: sta_hpr_ref_build_pyramid. Levels >= 1 lie side
// by side in one image (pass_hpr.h): level l - 1 is read at u_src_origin (of the position
// image, or of the pyramid image bound a second time), level l written at u_dst_origin.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_HPR_PYRAMID_IMAGE_SRC, rgba32f) readonly uniform image2D u_src;  // level l - 1
#ifdef STA_STAGED_STORES
// Staged (render/gl_staged.h): level l's texels, row by row; the pass copies them to
// u_dst_origin.
layout(std430, binding = STA_HPR_PYRAMID_BUFFER_DST) writeonly restrict buffer Staged {
    vec4 u_staged[];
};
#else
layout(binding = STA_HPR_PYRAMID_IMAGE_DST, rgba32f) writeonly uniform image2D u_dst; // level l
#endif
uniform ivec2 u_src_size; // logical size of level l - 1
uniform ivec2 u_dst_size; // logical size of level l
uniform ivec2 u_src_origin;
uniform ivec2 u_dst_origin;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_dst_size.x || p.y >= u_dst_size.y) {
        return;
    }
    vec4 best = vec4(0.0);
    bool found = false;
    for (int bj = 0; bj < 2; bj++) {
        for (int bi = 0; bi < 2; bi++) {
            ivec2 q = 2 * p + ivec2(bi, bj);
            if (q.x >= u_src_size.x || q.y >= u_src_size.y) {
                continue;
            }
            vec4 v = imageLoad(u_src, u_src_origin + q);
            if (v.w > 0.5 && (!found || -v.z < -best.z)) {
                best = v;
                found = true;
            }
        }
    }
#ifdef STA_STAGED_STORES
    u_staged[p.y * u_dst_size.x + p.x] = best;
#else
    imageStore(u_dst, u_dst_origin + p, best);
#endif
}
