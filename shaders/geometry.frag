// SPDX-License-Identifier: MIT
// Geometry pass: colour of the nearest point per pixel (depth test, reverse-Z).
in vec3 v_colour;
layout(location = 0) out vec4 o_colour;

void main()
{
    o_colour = vec4(v_colour, 1.0);
}
