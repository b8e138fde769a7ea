// SPDX-License-Identifier: MIT
// Mirror composite (render/pass_mirror.c): projective texturing of the reflected view
// onto the mirror's outline. For each pixel of the frame, the view ray meets the
// mirror's plane; inside the outline, and nearer than the point drawn there (if any),
// the pixel takes the reflected view's colour at the same row, mirrored column
// (the reflected camera is a proper one: its picture is the mirror's flipped).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;

layout(binding = STA_MIRROR_IMAGE_OUT, rgba8) uniform image2D u_out;
layout(binding = STA_MIRROR_SAMPLER_DEPTH) uniform sampler2D u_depth;
layout(binding = STA_MIRROR_SAMPLER_REFLECTED) uniform sampler2D u_reflected;
layout(binding = STA_MIRROR_SAMPLER_REFLECTED_DEPTH) uniform sampler2D u_reflected_depth;
layout(binding = STA_MIRROR_SAMPLER_FILLED) uniform sampler2D u_filled; // camera space, w > 0 valid

uniform ivec2 u_size;     // frame, pixels
uniform mat3 u_to_world;  // camera-space directions -> world (inverse view rotation)
uniform vec2 u_tan;       // tan(fov / 2) * aspect, tan(fov / 2)
uniform float u_near;     // metres (reverse-Z: depth = near / distance along the view axis)
uniform vec4 u_plane;     // camera-relative mirror plane: normal, offset (> 0: camera in front)
uniform vec3 u_centre;    // camera-relative centre of the outline
uniform vec3 u_axis_u;    // in-plane axes of the outline's (u, v)
uniform vec3 u_axis_v;
uniform vec2 u_outline[STA_MIRROR_OUTLINE_MAX];
uniform int u_count;
uniform vec3 u_background;
uniform int u_has_filled; // the pipeline filled the surface: it hides the mirror too

bool inside(vec2 p)
{
    bool in_ = false;
    for (int i = 0, j = u_count - 1; i < u_count; j = i++) {
        vec2 a = u_outline[i], b = u_outline[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) {
            in_ = !in_;
        }
    }
    return in_;
}

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    vec2 ndc = (vec2(p) + 0.5) / vec2(u_size) * 2.0 - 1.0;
    vec3 dir = u_to_world * vec3(ndc * u_tan, -1.0); // one metre along the view axis
    float along = dot(u_plane.xyz, dir);
    if (along >= 0.0) {
        return; // the ray does not meet the mirror's front
    }
    float t = -u_plane.w / along; // distance along the view axis
    vec3 h = t * dir - u_centre;
    if (!inside(vec2(dot(h, u_axis_u), dot(h, u_axis_v)))) {
        return;
    }
    if (texelFetch(u_depth, p, 0).r > u_near / t) {
        return; // a point in front of the mirror
    }
    // The raw points leave gaps a wall in front of the mirror does not have: where the
    // pipeline filled the surface, a filled position nearer than the mirror hides it.
    if (u_has_filled != 0) {
        vec4 f = texelFetch(u_filled, p, 0);
        if (f.w > 0.0 && -f.z < t * 0.999) {
            return;
        }
    }
    ivec2 q = ivec2(u_size.x - 1 - p.x, p.y);
    vec3 c = texelFetch(u_reflected_depth, q, 0).r > 0.0 ? texelFetch(u_reflected, q, 0).rgb
                                                          : u_background;
    imageStore(u_out, p, vec4(c, 1.0));
}
