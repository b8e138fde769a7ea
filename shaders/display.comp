// SPDX-License-Identifier: MIT
// Shows an intermediate buffer of the screen-space pipeline in the RGBA8 output:
// mode 0 the HPR labels over the point colours, 1 the filled colour, 2 the normals.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_DISPLAY_IMAGE_POSITION, rgba32f) readonly uniform image2D u_position;
layout(binding = STA_DISPLAY_IMAGE_COLOUR, rgba32f) readonly uniform image2D u_colour;
layout(binding = STA_DISPLAY_IMAGE_FILLED_COLOUR, rgba8) readonly uniform image2D u_filled_colour;
layout(binding = STA_DISPLAY_IMAGE_LABEL, r16f) readonly uniform image2D u_label;
layout(binding = STA_DISPLAY_IMAGE_NORMAL, rgba32f) readonly uniform image2D u_normal;
layout(binding = STA_DISPLAY_IMAGE_OUT, rgba8) writeonly uniform image2D u_out;
uniform vec2 u_size;
uniform int u_mode;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(u_size.x) || p.y >= int(u_size.y)) {
        return;
    }
    vec3 result = vec3(0.0);
    if (u_mode == 0) {
        float label = imageLoad(u_label, p).r;
        if (label == 1.0) {
            result = imageLoad(u_colour, p).rgb;        // visible point
        } else if (label == 2.0) {
            result = vec3(0.9, 0.1, 0.1);               // hidden point: removed
        } else if (label == 3.0) {
            result = vec3(0.1, 0.35, 0.1);              // hole: to be filled
        }
    } else if (u_mode == 1) {
        vec4 c = imageLoad(u_filled_colour, p); // alpha 1: the overlay's marked point
        if (imageLoad(u_position, p).w > 0.0 || c.a > 0.5) {
            result = c.rgb;
        }
    } else {
        vec4 n = imageLoad(u_normal, p);
        if (n.w > 0.0) {
            result = n.xyz * 0.5 + 0.5;
        }
    }
    imageStore(u_out, p, vec4(result, 1.0));
}
