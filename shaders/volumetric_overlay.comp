// SPDX-License-Identifier: MIT
// Volumetric classes, overlay step: each marked point is drawn over the shaded picture
// as a square splat in its own colour, nearest point first, unless a visible point of
// another class in the window is as near (the filled depth is no test: pull-push
// averages depths across wide gaps). One image read per window pixel
// (volumetric_window.glsl). The shaded pipeline draws them inside its shade pass
// instead; this pass serves the fill display.
// Twin: src/render/ref/volumetric_ref.c (sta_volumetric_overlay_ref).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_OUT, rgba8) writeonly uniform image2D u_out;
uniform ivec2 u_size;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    vec3 colour;
    if (vw_overlay_colour(p, u_size, colour)) {
        imageStore(u_out, p, vec4(clamp(colour, 0.0, 1.0), 1.0));
    }
}
