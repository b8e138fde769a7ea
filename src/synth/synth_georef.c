/* SPDX-License-Identifier: MIT
 * Georeference of a synthetic scene: the world origin, integer grid and CRS of each
 * origin choice, and the integer LAS coordinate of a scene-local value. Used by the
 * point sources (street scanner, analytic samplers) and the generator.
 */
#include <string.h>

#include "synth/synth.h"
#include "synth/synth_math.h"

static const char wkt_utm32n[] =
    "PROJCS[\"WGS 84 / UTM zone 32N\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS "
    "84\",6378137,298.257223563,AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],"
    "PRIMEM[\"Greenwich\",0,AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,"
    "AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]],PROJECTION[\"Transverse_"
    "Mercator\"],PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",9],"
    "PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],PARAMETER["
    "\"false_northing\",0],UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS[\"Easting\","
    "EAST],AXIS[\"Northing\",NORTH],AUTHORITY[\"EPSG\",\"32632\"]]";

static const char wkt_ecef[] =
    "GEOCCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563,"
    "AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
    "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS["
    "\"Geocentric X\",OTHER],AXIS[\"Geocentric Y\",OTHER],AXIS[\"Geocentric Z\",NORTH],"
    "AUTHORITY[\"EPSG\",\"4978\"]]";

void sta_synth_georef_init(sta_synth_origin origin, sta_synth_georef *g)
{
    // Offsets are round numbers; origins sit a non-round (but exactly representable)
    // number of millimetres from them, so a shift by the origin is visible in the data.
    static const double offsets[3][3] = { { 650000.0, 5400000.0, 0.0 },
                                          { 0.0, 0.0, 0.0 },
                                          { 4200000.0, 170000.0, 4780000.0 } };
    static const int64_t steps[3][3] = { { 241375, 1873625, 103250 },
                                         { 0, 0, 0 },
                                         { 1345125, 1234500, 123750 } };
    int k = origin == STA_SYNTH_ORIGIN_ZERO ? 1 : (origin == STA_SYNTH_ORIGIN_ECEF ? 2 : 0);
    memset(g, 0, sizeof(*g));
    for (int a = 0; a < 3; a++) {
        g->grid.scale[a] = 0.001;
        g->grid.offset[a] = offsets[k][a];
        g->origin_steps[a] = steps[k][a];
        g->origin[a] = offsets[k][a] + (double)steps[k][a] * 0.001;
    }
    g->crs = k == 0 ? "EPSG:32632" : (k == 2 ? "EPSG:4978" : "local");
    g->wkt = k == 0 ? wkt_utm32n : (k == 2 ? wkt_ecef : NULL);
}

int32_t sta_synth_georef_step(const sta_synth_georef *g, int axis, double local_m)
{
    // round half up: floor(x + 0.5)
    int64_t steps = sta_floor_i64(local_m / g->grid.scale[axis] + 0.5);
    return (int32_t)(steps + g->origin_steps[axis]);
}
