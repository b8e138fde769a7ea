// SPDX-License-Identifier: MIT
// Pyramidal normals at half resolution, step 3: every pixel's normal from the
// half-resolution normals of the even pixels (normals_upsample.glsl).
// Twin: src/render/ref/normals_pyramid_ref.c.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_NORMALS_PYRAMID_UPSAMPLE_IMAGE_NORMAL, rgba32f)
    writeonly uniform image2D u_normal;
uniform ivec2 u_size;

void main()
{
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    if (q.x >= u_size.x || q.y >= u_size.y) {
        return;
    }
    imageStore(u_normal, q, np_upsample(q, imageLoad(u_points, q)));
}
