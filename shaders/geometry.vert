// SPDX-License-Identifier: MIT
// Geometry pass: one pixel per point. Positions arrive node-relative and quantized
// (stream/gpu_points.h); u_node_origin is the node corner minus the camera position,
// computed in double on the CPU, so the scene's distance from the origin costs no
// precision here.
layout(location = STA_ATTRIB_POSITION_INTENSITY) in uvec4 a_position_intensity;
layout(location = STA_ATTRIB_COLOUR_CLASS) in uvec4 a_colour_class;
layout(location = STA_ATTRIB_RETURNS) in uvec4 a_returns;

uniform vec3 u_node_origin;    // metres, camera-relative
uniform vec3 u_step;           // metres per quantisation step
uniform mat4 u_view_rotation;  // world directions -> camera space
uniform mat4 u_projection;     // reverse-Z, infinite far
uniform int u_colour_mode;     // STA_COLOUR_*
uniform vec2 u_elevation;      // (camera z - min z, 1 / (max z - min z))
uniform float u_intensity_scale; // 1 / largest intensity

out vec3 v_colour;

vec3 ramp(float t)
{
    // A perceptually ordered blue -> green -> yellow ramp.
    t = clamp(t, 0.0, 1.0);
    vec3 a = vec3(0.27, 0.00, 0.33), b = vec3(0.13, 0.57, 0.55), c = vec3(0.99, 0.91, 0.14);
    return t < 0.5 ? mix(a, b, t * 2.0) : mix(b, c, t * 2.0 - 1.0);
}

vec3 class_colour(uint c)
{
    // ASPRS standard classes (LAS 1.4 table 17).
    if (c == 2u) return vec3(0.65, 0.50, 0.35);              // ground
    if (c == 3u) return vec3(0.60, 0.85, 0.45);              // low vegetation
    if (c == 4u) return vec3(0.30, 0.70, 0.30);              // medium vegetation
    if (c == 5u) return vec3(0.10, 0.50, 0.15);              // high vegetation
    if (c == 6u) return vec3(0.85, 0.35, 0.25);              // building
    if (c == 7u || c == 18u) return vec3(1.00, 0.00, 1.00);  // noise
    if (c == 9u) return vec3(0.20, 0.40, 0.90);              // water
    if (c == 10u) return vec3(0.55, 0.35, 0.60);             // rail
    if (c == 11u) return vec3(0.35, 0.35, 0.38);             // road surface
    if (c == 13u || c == 14u) return vec3(0.95, 0.85, 0.10); // wire
    if (c == 15u) return vec3(0.80, 0.55, 0.10);             // transmission tower / pole
    if (c == 17u) return vec3(0.60, 0.60, 0.75);             // bridge deck
    return vec3(0.75, 0.75, 0.75);                           // unclassified and others
}

vec3 return_colour(uint r, uint n)
{
    if (n <= 1u) return vec3(0.85, 0.85, 0.85); // single return
    if (r == 1u) return vec3(0.90, 0.30, 0.20); // first of many
    if (r >= n) return vec3(0.20, 0.40, 0.90);  // last of many
    return vec3(0.30, 0.80, 0.30);              // intermediate
}

void main()
{
    vec3 relative = u_node_origin + vec3(a_position_intensity.xyz) * u_step;
    gl_Position = u_projection * (u_view_rotation * vec4(relative, 1.0));
    gl_PointSize = 1.0;
    if (u_colour_mode == STA_COLOUR_INTENSITY) {
        v_colour = vec3(sqrt(clamp(float(a_position_intensity.w) * u_intensity_scale, 0.0, 1.0)));
    } else if (u_colour_mode == STA_COLOUR_ELEVATION) {
        v_colour = ramp((relative.z + u_elevation.x) * u_elevation.y);
    } else if (u_colour_mode == STA_COLOUR_CLASSIFICATION) {
        v_colour = class_colour(a_colour_class.w);
    } else if (u_colour_mode == STA_COLOUR_RETURN_NUMBER) {
        v_colour = return_colour(a_returns.x, a_returns.y);
    } else {
        v_colour = vec3(a_colour_class.xyz) / 255.0;
    }
}
