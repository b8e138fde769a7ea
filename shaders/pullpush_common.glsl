// SPDX-License-Identifier: MIT
// Shared by the pull-push shaders. PP_LABEL_BACKGROUND and PP_LABEL_VISIBLE are
// injected by the pass from STA_LABEL_* (screen_space.h).

// Labels are small integers stored as floats.
bool pp_is_label(float label, float value)
{
    return abs(label - value) < 0.5;
}

// The initial weight of a level-0 input texel: 1 for a drawn point (w > 0) that HPR
// labelled VISIBLE (or any drawn point without labels) and that is not of a volumetric
// class (w = PP_POSITION_W_MARKED, screen_space.h), 0 otherwise.
float pp_input_weight(vec4 point, float label, bool has_label)
{
    bool visible = !has_label || pp_is_label(label, PP_LABEL_VISIBLE);
    return point.w > 0.0 && point.w != PP_POSITION_W_MARKED && visible ? 1.0 : 0.0;
}

// The see-through share of a level-0 input texel: 1 for a see-through return
// (w from PP_POSITION_W_SEE_THROUGH_MIN on, screen_space.h: window glass), 0 otherwise.
float pp_input_share(vec4 point)
{
    return point.w >= PP_POSITION_W_SEE_THROUGH_MIN ? 1.0 : 0.0;
}

// A glass tap (see-through share from PP_GLASS_SHARE on) in front of the farthest solid tap
// (depth solid_d, 0 where none): the window in front of its room; it gives no value.
bool pp_glass_over_solid(float d, float share, float solid_d)
{
    return share >= PP_GLASS_SHARE && solid_d > d * (1.0 + PP_GLASS_GAP);
}

#ifdef STA_STAGED_STORES
// Staged stores (render/gl_staged.h; llvmpipe stores an RGBA32F image texel by texel,
// channel by channel): the level written goes to these buffers, row by row, and the pass
// copies them into its textures after the dispatch.
layout(std430, binding = STA_PULLPUSH_BUFFER_OUT_POSITION) writeonly restrict buffer
    StagedPosition {
    vec4 u_staged_position[];
};
layout(std430, binding = STA_PULLPUSH_BUFFER_OUT_COLOUR) writeonly restrict buffer StagedColour {
    vec4 u_staged_colour[];
};
#endif
