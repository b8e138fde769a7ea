// SPDX-License-Identifier: MIT
// Eye-dome lighting (Boucheny 2009): darkens a pixel by how much its 8 neighbours at a
// radius of `u_radius` pixels are nearer to the eye, in log2 depth. Needs depth only.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_EDL_IMAGE_POSITION, rgba32f) readonly uniform image2D u_position;
layout(binding = STA_EDL_IMAGE_COLOUR, rgba32f) readonly uniform image2D u_colour;
layout(binding = STA_EDL_IMAGE_OUT, rgba8) writeonly uniform image2D u_out;
uniform vec2 u_size;
uniform float u_radius;   // pixels
uniform float u_strength; // response scale
uniform vec3 u_background;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(u_size);
    if (p.x >= size.x || p.y >= size.y) {
        return;
    }
    vec4 position = imageLoad(u_position, p);
    if (position.w <= 0.0) {
        imageStore(u_out, p, vec4(u_background, 1.0));
        return;
    }
    float log_depth = log2(-position.z);
    float response = 0.0;
    for (int i = 0; i < 8; i++) {
        float angle = float(i) * 0.78539816339;
        ivec2 q = p + ivec2(round(vec2(cos(angle), sin(angle)) * u_radius));
        q = clamp(q, ivec2(0), size - 1);
        vec4 neighbour = imageLoad(u_position, q);
        // Empty neighbours count as far away, like the sky behind a silhouette.
        float other = neighbour.w > 0.0 ? log2(-neighbour.z) : log_depth + 10.0;
        response += max(0.0, log_depth - other);
    }
    float shade = exp(-u_strength * response / 8.0);
    imageStore(u_out, p, vec4(clamp(imageLoad(u_colour, p).rgb * shade, 0.0, 1.0), 1.0));
}
