/* SPDX-License-Identifier: MIT
 * Which rasteriser the geometry pass runs, and why (no GL: tested without a driver). */
#include <stdio.h>
#include <string.h>

#include "render/pass_geometry.h"

void sta_geometry_options_defaults(sta_geometry_options *o)
{
    if (o->raster != STA_RASTER_COMPUTE && o->raster != STA_RASTER_POINTS) {
        o->raster = STA_RASTER_DEFAULT_METHOD;
    }
}

void sta_geometry_choose(const sta_geometry_options *options, bool has_atomic_int64,
                         sta_geometry_choice *out)
{
    sta_geometry_options o = options ? *options : (sta_geometry_options){ 0 };
    bool is_default = o.raster == STA_RASTER_DEFAULT;
    sta_geometry_options_defaults(&o);
    memset(out, 0, sizeof(*out));
    out->raster = o.raster;
    const char *why = is_default ? "the default" : "as asked";
    if (o.raster == STA_RASTER_POINTS) {
        snprintf(out->reason, sizeof(out->reason), "geometry pass: GL_POINTS (%s)", why);
        return;
    }
    out->packed = has_atomic_int64 && !o.force_32bit_atomics;
    const char *atomics = out->packed ? "one pass, 64-bit atomics"
                          : has_atomic_int64
                              ? "two passes, 32-bit atomics: 64-bit ones switched off"
                              : "two passes, 32-bit atomics: no 64-bit ones (GL_ARB_ or "
                                "GL_NV_shader_atomic_int64)";
    snprintf(out->reason, sizeof(out->reason), "geometry pass: compute rasteriser (%s; %s)", why,
             atomics);
}

int sta_raster_method_from_name(const char *name)
{
    if (strcmp(name, "compute") == 0) {
        return STA_RASTER_COMPUTE;
    }
    if (strcmp(name, "points") == 0) {
        return STA_RASTER_POINTS;
    }
    return -1;
}

const char *sta_raster_method_name(int method)
{
    return method == STA_RASTER_POINTS ? "points" : "compute";
}
