// SPDX-License-Identifier: MIT
// Geometry pass: colour of the nearest point per pixel (depth test, reverse-Z), its id
// and, where the pass attached a class texture (sta_pass_geometry_set_class_out), its class.
flat in vec3 v_colour;
flat in uvec2 v_id;
flat in uint v_class;
layout(location = STA_GEOMETRY_OUT_COLOUR) out vec4 o_colour;
layout(location = STA_GEOMETRY_OUT_ID) out uvec2 o_id;
layout(location = STA_GEOMETRY_OUT_CLASS) out uint o_class;

void main()
{
    o_colour = vec4(v_colour, 1.0);
    o_id = v_id;
    o_class = v_class;
}
