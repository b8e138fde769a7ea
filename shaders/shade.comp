// SPDX-License-Identifier: MIT
// Deferred shading: Blinn-Phong with a headlight from the reconstructed positions and
// normals and the (filled) point colours. Pixels without a surface get the background.
// The volumetric classes' marked points were drawn into the filled colour before, on the
// tiles they reach (volumetric_overlay.comp): alpha 1, shown unlit (screen_space.h). With STA_SHADE_UPSAMPLE (and
// normals_upsample.glsl) the half-resolution normals are upsampled here instead of read
// from the normal image: again the same picture, one full-screen pass fewer.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_SHADE_IMAGE_POSITION, rgba32f) readonly uniform image2D u_position;
layout(binding = STA_SHADE_IMAGE_COLOUR, rgba8) readonly uniform image2D u_colour;
#ifndef STA_SHADE_UPSAMPLE
layout(binding = STA_SHADE_IMAGE_NORMAL, rgba32f) readonly uniform image2D u_normal;
#endif
layout(binding = STA_SHADE_IMAGE_OUT, rgba8) writeonly uniform image2D u_out;
uniform vec2 u_size;
uniform vec4 u_light; // ambient, diffuse, specular, shininess
uniform vec3 u_background;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(u_size.x) || p.y >= int(u_size.y)) {
        return;
    }
    vec4 position = imageLoad(u_position, p);
#ifdef STA_SHADE_UPSAMPLE
    vec4 normal = np_upsample(p, position); // the same normal the upsample pass would store
#else
    vec4 normal = imageLoad(u_normal, p);
#endif
    vec3 result = u_background;
    vec4 colour = imageLoad(u_colour, p);
    if (position.w > 0.0) {
        vec3 albedo = colour.rgb;
        float len = length(position.xyz);
        vec3 to_eye = len > 0.0 ? -position.xyz / len : vec3(0.0, 0.0, 1.0);
        if (normal.w > 0.0) {
            // Headlight: the light sits at the eye, so the half vector is the view vector.
            float lambert = max(dot(normal.xyz, to_eye), 0.0);
            float specular = pow(lambert, u_light.w);
            result = albedo * (u_light.x + u_light.y * lambert) + vec3(u_light.z * specular);
        } else {
            result = albedo * (u_light.x + u_light.y); // no normal: unlit, as if facing us
        }
    }
    result = colour.a > 0.5 ? colour.rgb : result; // the overlay's marked point, unlit
    imageStore(u_out, p, vec4(clamp(result, 0.0, 1.0), 1.0));
}
