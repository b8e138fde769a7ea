#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The compute rasteriser's one-pass 64-bit variant (STA_RASTER_PACKED) cannot compile on
# llvmpipe (no GL_ARB_shader_atomic_int64), so CI checks its shaders with glslang:
# the preamble of bindings.h's defines, the extensions and defines that
# render/raster_compute.c adds, then the sources, as sta_gl_program_create joins them.
# glslang knows GL_EXT_shader_atomic_int64 (the same atomicMax on uint64_t) but not the
# ARB name, so the EXT one stands in for it.
# usage: check_packed_raster.sh SHADER_DIR BINDINGS_H SCREEN_SPACE_H WORK_DIR
set -euo pipefail
shaders=$1 bindings=$2 screen_space=$3 work=$4
command -v glslangValidator >/dev/null || {
    echo "glslangValidator missing (Debian: glslang-tools, scripts/install-deps.sh)" >&2
    exit 1
}
mkdir -p "$work"
preamble() {
    echo "#version 450 core"
    grep -h '^#define STA_' "$bindings" "$screen_space" | grep -v 'STA_BINDING_DEFINES\|_H$'
    echo "#extension GL_ARB_gpu_shader_int64 : require"
    echo "#extension GL_EXT_shader_atomic_int64 : require"
    echo "#define STA_RASTER_PACKED 1"
    echo "#define STA_RASTER_SUBPIXEL_BITS 8"
    echo "#define STA_RASTER_STEP STA_RASTER_STEP_PACKED"
    echo "#define STA_RASTER_COLOUR_MODE STA_COLOUR_RGB"
}
# The point step in both builds: one pixel per point, and footprints (STA_RASTER_WIDE).
for wide in 0 1; do
    { preamble; echo "#define STA_RASTER_WIDE $wide"; cat "$shaders/raster_common.glsl" \
        "$shaders/point_footprint.glsl" "$shaders/raster_points.comp"; } >"$work/packed$wide.comp"
done
{ preamble; cat "$shaders/geometry_colour.glsl" "$shaders/raster_common.glsl" \
    "$shaders/raster_resolve.frag"; } >"$work/packed.frag"
{ preamble; cat "$shaders/geometry_colour.glsl" "$shaders/raster_common.glsl" \
    "$shaders/raster_resolve.vert"; } >"$work/packed.vert"
status=0
for file in packed0.comp packed1.comp packed.frag packed.vert; do
    glslangValidator "$work/$file" || status=1
done
exit $status
