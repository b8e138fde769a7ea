// SPDX-License-Identifier: MIT
// Splats: the round disk out of its square, shaded with its normal. The square lies in
// the disk's plane, so the perspective-correct v_uv and the rasterised depth are those
// of the eye ray's intersection with the disk: the depth test is per fragment, exact
// where disks cross (no gl_FragDepth needed, which keeps early depth testing).
flat in vec3 v_colour;
flat in uvec2 v_id;
flat in vec3 v_normal;
in vec2 v_uv;
in vec3 v_position;

uniform vec4 u_light; // ambient, diffuse, specular, shininess (as shaders/shade.comp)
uniform bool u_lit;   // false: the plain colour

layout(location = STA_GEOMETRY_OUT_COLOUR) out vec4 o_colour;
layout(location = STA_GEOMETRY_OUT_ID) out uvec2 o_id;

void main()
{
    if (dot(v_uv, v_uv) > 1.0) {
        discard;
    }
    vec3 colour = u_lit ? splat_shade(v_colour, v_normal, v_position, u_light) : v_colour;
    o_colour = vec4(colour, 1.0);
    o_id = v_id;
}
