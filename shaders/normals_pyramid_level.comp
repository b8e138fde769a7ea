// SPDX-License-Identifier: MIT
// Pyramidal normals (Bouchiba et al. 2018, 3.3), step 1: the normal of every texel of
// one pyramid level l >= 1 (pn_point_normal in pullpush_normals.glsl), written into the
// level's block of the normal atlas: xyz the unit normal (zero where none), w its
// tangent plane's offset dot(n, p) for the gather's plane test.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
#ifdef STA_STAGED_STORES
// Staged (render/gl_staged.h): the level's texels, row by row; the pass copies them to
// u_offset.
layout(std430, binding = STA_NORMALS_PYRAMID_LEVEL_BUFFER_ATLAS) writeonly restrict buffer Staged {
    vec4 u_staged[];
};
#else
layout(binding = STA_NORMALS_PYRAMID_LEVEL_IMAGE_ATLAS, rgba32f) writeonly uniform image2D u_atlas;
#endif
uniform ivec2 u_size;   // level size
uniform ivec2 u_offset; // the level's origin in the atlas
uniform float u_jump2;   // squared jump ratio (pn_difference)
uniform float u_texel_m; // the texel's footprint per metre of depth

void main()
{
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    if (q.x >= u_size.x || q.y >= u_size.y) {
        return;
    }
    vec3 n;
    bool valid = pn_point_normal(q, u_size, u_jump2, u_texel_m, n);
    vec3 p = imageLoad(u_points, q).xyz;
    vec4 result = valid ? vec4(n, np_dot(n, p)) : vec4(0.0);
#ifdef STA_STAGED_STORES
    u_staged[q.y * u_size.x + q.x] = result;
#else
    imageStore(u_atlas, u_offset + q, result);
#endif
}
