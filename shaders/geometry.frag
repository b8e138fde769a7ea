// SPDX-License-Identifier: MIT
// Geometry pass: colour of the nearest point per pixel (depth test, reverse-Z) and its id.
flat in vec3 v_colour;
flat in uvec2 v_id;
layout(location = STA_GEOMETRY_OUT_COLOUR) out vec4 o_colour;
layout(location = STA_GEOMETRY_OUT_ID) out uvec2 o_id;

void main()
{
    o_colour = vec4(v_colour, 1.0);
    o_id = v_id;
}
