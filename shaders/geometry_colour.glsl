// SPDX-License-Identifier: MIT
// A point's colour in each colour mode (STA_COLOUR_*), shared by the GL_POINTS vertex
// shader and the compute rasteriser's resolve, so both paths colour a point alike.

// Height above ground (STA_COLOUR_HEIGHT): the ground model as a texture over the plan,
// placed camera-relative on the CPU (render/ground_texture.c).
layout(binding = STA_GEOMETRY_SAMPLER_GROUND) uniform sampler2D u_ground;
uniform vec4 u_ground_frame; // camera-relative x, y of the grid's corner; its width, height (m)
uniform vec2 u_ground_height; // ground heights' origin minus camera z (m); 1 / ramp span (1/m)

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

// The colour of one point: its attributes as the vertex stage reads them (position and
// intensity, colour and class, returns), its camera-relative position for the elevation
// and height ramps, and the colour uniforms of the pass.
vec3 point_colour(uvec4 position_intensity, uvec4 colour_class, uvec4 returns, vec3 relative,
                  int mode, vec2 elevation, float intensity_scale)
{
    float relative_z = relative.z;
    if (mode == STA_COLOUR_HEIGHT) {
        vec2 uv = (relative.xy - u_ground_frame.xy) / u_ground_frame.zw;
        float ground = texture(u_ground, uv).r + u_ground_height.x;
        return ramp((relative_z - ground) * u_ground_height.y);
    }
    if (mode == STA_COLOUR_INTENSITY) {
        return vec3(sqrt(clamp(float(position_intensity.w) * intensity_scale, 0.0, 1.0)));
    } else if (mode == STA_COLOUR_ELEVATION) {
        return ramp((relative_z + elevation.x) * elevation.y);
    } else if (mode == STA_COLOUR_CLASSIFICATION) {
        return class_colour(colour_class.w);
    } else if (mode == STA_COLOUR_RETURN_NUMBER) {
        return return_colour(returns.x, returns.y);
    }
    return vec3(colour_class.xyz) / 255.0;
}
