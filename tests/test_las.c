/* SPDX-License-Identifier: MIT
 * Tests for the LAS reader (src/io/las*.c) through the generic io/cloud.h interface.
 *
 * - Every LAS file in ../shared/data/las is checked against the facts that
 *   ../shared/data/README.md states for it (the table below was transcribed from the
 *   README by a one-off script): header fields, VLRs, EVLRs, WKT, extra dimensions,
 *   and, after reading every point, the count, the extent, the GPS time range and
 *   the class histogram. The files broken by design have their own cases.
 * - Point fields are compared with a small independent decoder written here (and, for
 *   the first and last points, with numbers extracted by python3's struct module).
 * - Headers that lie, truncations, allocation failures, and point formats 5, 9 and 10
 *   (which exist in no public uncompressed file) are built in memory.
 *
 * Extent tolerance: where the README gives the actual extent of the points, the
 * reader's must match within half a scale step (plus the README's 10-digit rounding).
 * Where it gives only the header bbox (which it states equals the points' extent),
 * one full step is allowed: libLAS writes the bbox of the unquantised coordinates
 * (liblas_*.las: header min x 470692.4475, stored X 47069244 at scale 0.01).
 */
#include "test_support.h"

#include <dirent.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/log.h"
#include "io/cloud.h"
#include "io/las.h"

typedef struct vlr_fact {
    const char *user_id;
    unsigned record_id;
    unsigned long long length;
} vlr_fact;

typedef struct dim_fact {
    const char *name;
    unsigned data_type;
    unsigned options;
} dim_fact;

typedef struct class_fact {
    unsigned classification;
    unsigned long long count;
} class_fact;

typedef struct las_fact {
    const char *file;
    int version_minor;
    int point_format;
    unsigned record_length;
    size_t extra_size;
    unsigned long long point_count;
    unsigned long long legacy_point_count;
    unsigned header_size;
    unsigned offset_to_point_data;
    size_t vlr_count;
    size_t evlr_count;
    double scale[3];
    double offset[3];
    double extent_min[3]; /* actual extent, or header bbox when !extent_is_actual */
    double extent_max[3];
    bool extent_is_actual;
    const char *software;
    const char *system;
    unsigned creation_year;
    unsigned creation_day;
    unsigned global_encoding;
    const vlr_fact *vlrs; /* the first listed_vlrs VLRs (the README lists at most 6) */
    size_t listed_vlrs;
    const vlr_fact *evlrs;
    size_t listed_evlrs;
    const char *wkt_prefix; /* NULL: no LASF_Projection/2112 record */
    const dim_fact *dims;   /* Extra Bytes VLR fields as the README lists them */
    size_t dim_count;
    bool has_gps_range;
    double gps_min, gps_max;
    const class_fact *classes;
    size_t class_count;
} las_fact;

/* Transcribed from ../shared/data/README.md ("Files in detail"). */
static const las_fact corpus_facts[] = {
    {
        .file = "las/liblas_1.0_0.las",
        .version_minor = 0,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 440,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/liblas_1.0_1.las",
        .version_minor = 0,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 440,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .has_gps_range = true,
        .gps_min = 1205902800,
        .gps_max = 1205902800,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/TO_core_last_clip.las",
        .version_minor = 0,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 8,
        .legacy_point_count = 8,
        .header_size = 227,
        .offset_to_point_data = 229,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 630262.3, 4834500, 50.9 },
        .extent_max = { 630346.83, 4834500, 55.26 },
        .extent_is_actual = false,
        .software = "TerraScan",
        .system = "",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 413665.2336,
        .gps_max = 414094.8462,
        .classes = (const class_fact[]){ { 1, 8 } },
        .class_count = 1,
    },
    {
        .file = "las/point10-1.0.las",
        .version_minor = 0,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 1, 1, 1 },
        .offset = { 0, 0, 0 },
        .extent_min = { 1, 2, 3 },
        .extent_max = { 1, 2, 3 },
        .extent_is_actual = false,
        .software = "LASzip DLL 3.4 r3 (191111)",
        .system = "",
        .creation_year = 2023,
        .creation_day = 200,
        .global_encoding = 0,
        .classes = (const class_fact[]){ { 5, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/Example.las",
        .version_minor = 0,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 30,
        .legacy_point_count = 30,
        .header_size = 227,
        .offset_to_point_data = 405,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.001, 0.001, 0.001 },
        .offset = { 600000, 6500000, 0 },
        .extent_min = { 339002.889, 5248000.001, 973.145 },
        .extent_max = { 339015.116, 5248001.244, 978.345 },
        .extent_is_actual = false,
        .software = "las2las (version 201011)",
        .system = "LAStools (c) by rapidlasso GmbH",
        .creation_year = 2011,
        .creation_day = 343,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 40 }, { "LAStools", 10, 28 } },
        .listed_vlrs = 2,
        .has_gps_range = true,
        .gps_min = 269347.2814,
        .gps_max = 269347.6729,
        .classes = (const class_fact[]){ { 1, 27 }, { 2, 3 } },
        .class_count = 2,
    },
    {
        .file = "las/liblas_1.1_0.las",
        .version_minor = 1,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 438,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/liblas_1.1_1.las",
        .version_minor = 1,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 438,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .has_gps_range = true,
        .gps_min = 1205902800,
        .gps_max = 1205902800,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/simple1_1.las",
        .version_minor = 1,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1065,
        .legacy_point_count = 1065,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 635619.85, 848899.7, 406.59 },
        .extent_max = { 638982.55, 853535.43, 586.38 },
        .extent_is_actual = false,
        .software = "las2las (version 200216)",
        .system = "LAStools (c) by rapidlasso GmbH",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 245370.4171,
        .gps_max = 249783.1622,
        .classes = (const class_fact[]){ { 1, 789 }, { 2, 276 } },
        .class_count = 2,
    },
    {
        .file = "las/lots_of_vlr.las",
        .version_minor = 1,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 81891,
        .vlr_count = 390,
        .evlr_count = 0,
        .scale = { 0.001, 0.001, 0.001 },
        .offset = { 0, 0, 0 },
        .extent_min = { 715001.346, 839349.171, 17.275 },
        .extent_max = { 715001.346, 839349.171, 17.275 },
        .extent_is_actual = false,
        .software = "Merrick LiDAR Processing System",
        .system = "",
        .creation_year = 2002,
        .creation_day = 1,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "Merrick", 101, 342 },
                                    { "Merrick", 102, 64 },
                                    { "Merrick", 102, 64 },
                                    { "Merrick", 102, 64 },
                                    { "Merrick", 102, 64 },
                                    { "Merrick", 102, 64 } },
        .listed_vlrs = 6,
        .has_gps_range = true,
        .gps_min = 221770.4329,
        .gps_max = 221770.4329,
        .classes = (const class_fact[]){ { 1, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/liblas_1.2_0.las",
        .version_minor = 2,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 438,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/liblas_1.2_1.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 438,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .has_gps_range = true,
        .gps_min = 1205902800,
        .gps_max = 1205902800,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/liblas_1.2_2.las",
        .version_minor = 2,
        .point_format = 2,
        .record_length = 26,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 438,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/liblas_1.2_3.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 438,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .has_gps_range = true,
        .gps_min = 1205902800,
        .gps_max = 1205902800,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/point10.las",
        .version_minor = 2,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 1065,
        .legacy_point_count = 1065,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 493994.87, 4877429.62, 123.93 },
        .extent_max = { 494993.68, 4878817.02, 178.73 },
        .extent_is_actual = false,
        .software = "TerraScan",
        .system = "",
        .creation_year = 2014,
        .creation_day = 113,
        .global_encoding = 0,
        .classes = (const class_fact[]){ { 1, 789 }, { 2, 276 } },
        .class_count = 2,
    },
    {
        .file = "las/point-time.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1065,
        .legacy_point_count = 1065,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 493994.87, 4877429.62, 123.93 },
        .extent_max = { 494993.68, 4878817.02, 178.73 },
        .extent_is_actual = false,
        .software = "TerraScan",
        .system = "",
        .creation_year = 2014,
        .creation_day = 128,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 245370.4171,
        .gps_max = 249783.1622,
        .classes = (const class_fact[]){ { 1, 789 }, { 2, 276 } },
        .class_count = 2,
    },
    {
        .file = "las/point-color.las",
        .version_minor = 2,
        .point_format = 2,
        .record_length = 26,
        .extra_size = 0,
        .point_count = 1065,
        .legacy_point_count = 1065,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 493994.87, 4877429.62, 123.93 },
        .extent_max = { 494993.68, 4878817.02, 178.73 },
        .extent_is_actual = false,
        .software = "TerraScan",
        .system = "",
        .creation_year = 2014,
        .creation_day = 128,
        .global_encoding = 0,
        .classes = (const class_fact[]){ { 1, 789 }, { 2, 276 } },
        .class_count = 2,
    },
    {
        .file = "las/point-time-color.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 1065,
        .legacy_point_count = 1065,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 493994.87, 4877429.62, 123.93 },
        .extent_max = { 494993.68, 4878817.02, 178.73 },
        .extent_is_actual = false,
        .software = "TerraScan",
        .system = "",
        .creation_year = 2014,
        .creation_day = 128,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 245370.4171,
        .gps_max = 249783.1622,
        .classes = (const class_fact[]){ { 1, 789 }, { 2, 276 } },
        .class_count = 2,
    },
    {
        .file = "las/extra-bytes.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 61,
        .extra_size = 27,
        .point_count = 1065,
        .legacy_point_count = 1065,
        .header_size = 227,
        .offset_to_point_data = 1241,
        .vlr_count = 1,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 635619.85, 848899.7, 406.59 },
        .extent_max = { 638982.55, 853535.43, 586.38 },
        .extent_is_actual = false,
        .software = "las2las (version 140915)",
        .system = "LAStools (c) by rapidlasso GmbH",
        .creation_year = 2015,
        .creation_day = 53,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Spec", 4, 960 } },
        .listed_vlrs = 1,
        .dims = (const dim_fact[]){ { "Colors", 23, 0 },
                                    { "Reserved", 0, 7 },
                                    { "Flags", 12, 0 },
                                    { "Intensity", 5, 0 },
                                    { "Time", 7, 0 } },
        .dim_count = 5,
        .has_gps_range = true,
        .gps_min = 245370.4171,
        .gps_max = 249783.1622,
        .classes = (const class_fact[]){ { 1, 789 }, { 2, 276 } },
        .class_count = 2,
    },
    {
        .file = "las/simple.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 1065,
        .legacy_point_count = 1065,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 635619.85, 848899.7, 406.59 },
        .extent_max = { 638982.55, 853535.43, 586.38 },
        .extent_is_actual = false,
        .software = "TerraScan",
        .system = "",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 245370.4171,
        .gps_max = 249783.1622,
        .classes = (const class_fact[]){ { 1, 789 }, { 2, 276 } },
        .class_count = 2,
    },
    {
        .file = "las/autzen_trim.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 110000,
        .legacy_point_count = 110000,
        .header_size = 227,
        .offset_to_point_data = 2038,
        .vlr_count = 5,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 636001.76, 848935.2, 406.26 },
        .extent_max = { 637179.22, 849497.9, 520.51 },
        .extent_is_actual = false,
        .software = "PDAL 1.0.0 (9e8465)",
        .system = "PDAL",
        .creation_year = 2015,
        .creation_day = 253,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 184 },
                                    { "LASF_Projection", 34736, 72 },
                                    { "LASF_Projection", 34737, 99 },
                                    { "LASF_Projection", 2112, 593 },
                                    { "liblas", 2112, 593 } },
        .listed_vlrs = 5,
        .wkt_prefix = "PROJCS[\"NAD_1983_HARN_Lambert_Conformal_Conic\"",
        .has_gps_range = true,
        .gps_min = 245379.3984,
        .gps_max = 245385.9111,
        .classes = (const class_fact[]){ { 1, 83893 }, { 2, 26107 } },
        .class_count = 2,
    },
    {
        .file = "las/autzen-point-format-3.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 106,
        .legacy_point_count = 106,
        .header_size = 227,
        .offset_to_point_data = 1994,
        .vlr_count = 4,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 635616.31, 848977.79, 407.35 },
        .extent_max = { 638864.6, 853362.37, 536.84 },
        .extent_is_actual = false,
        .software = "TerraScan",
        .system = "",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "liblas", 2112, 720 },
                                    { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 47 },
                                    { "liblas", 2112, 720 } },
        .listed_vlrs = 4,
        .has_gps_range = true,
        .gps_min = 245372.9067,
        .gps_max = 249780.6156,
        .classes = (const class_fact[]){ { 1, 82 }, { 2, 24 } },
        .class_count = 2,
    },
    {
        .file = "las/1815.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1247,
        .legacy_point_count = 1247,
        .header_size = 227,
        .offset_to_point_data = 520,
        .vlr_count = 3,
        .evlr_count = 0,
        .scale = { 1e-05, 1e-05, 1e-05 },
        .offset = { 2014969.123, 6493024.647, 76.5526028 },
        .extent_min = { 2014000.418, 6493002.071, 87.9591828 },
        .extent_max = { 2014999.693, 6493999.93, 124.0741328 },
        .extent_is_actual = false,
        .software = "las2las (version 170718)",
        .system = "LAStools (c) by rapidlasso GmbH",
        .creation_year = 2017,
        .creation_day = 138,
        .global_encoding = 1,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 96 },
                                    { "LASF_Projection", 34736, 0 },
                                    { "LASF_Projection", 34737, 35 } },
        .listed_vlrs = 3,
        .has_gps_range = true,
        .gps_min = 175050096,
        .gps_max = 175511728,
        .classes = (const class_fact[]){ { 1, 1003 }, { 2, 244 } },
        .class_count = 2,
    },
    {
        .file = "las/Megaplot.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 81590,
        .legacy_point_count = 81590,
        .header_size = 227,
        .offset_to_point_data = 321,
        .vlr_count = 1,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 684766.39, 5017773.08, 0 },
        .extent_max = { 684993.29, 5018007.25, 29.97 },
        .extent_is_actual = false,
        .software = "las2las (version 171231)",
        .system = "LAStools (c) by rapidlasso GmbH",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 40 } },
        .listed_vlrs = 1,
        .has_gps_range = true,
        .gps_min = 483825.8941,
        .gps_max = 484376.7967,
        .classes = (const class_fact[]){ { 1, 74201 }, { 2, 7389 } },
        .class_count = 2,
    },
    {
        .file = "las/MixedConifer.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 36,
        .extra_size = 8,
        .point_count = 37657,
        .legacy_point_count = 37657,
        .header_size = 227,
        .offset_to_point_data = 567,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 481260, 3812921.09, 0 },
        .extent_max = { 481349.99, 3813010.99, 32.07 },
        .extent_is_actual = false,
        .software = "las2las (version 171231)",
        .system = "LAStools (c) by rapidlasso GmbH",
        .creation_year = 2017,
        .creation_day = 0,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Spec", 4, 192 }, { "LASF_Projection", 34735, 40 } },
        .listed_vlrs = 2,
        .dims = (const dim_fact[]){ { "treeID", 10, 7 } },
        .dim_count = 1,
        .has_gps_range = true,
        .gps_min = 149928.3873,
        .gps_max = 152207.4047,
        .classes = (const class_fact[]){ { 1, 31832 }, { 2, 5820 }, { 11, 5 } },
        .class_count = 3,
    },
    {
        .file = "las/extra_byte.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 32,
        .extra_size = 4,
        .point_count = 62,
        .legacy_point_count = 62,
        .header_size = 227,
        .offset_to_point_data = 1117,
        .vlr_count = 4,
        .evlr_count = 0,
        .scale = { 0.001, 0.001, 0.001 },
        .offset = { 286553, 578790, 39 },
        .extent_min = { 286299.189, 580699.582, 20.124 },
        .extent_max = { 286318.741, 580701.586, 41.419 },
        .extent_is_actual = false,
        .software = "las2las (version 201011)",
        .system = "LAStools (c) by rapidlasso GmbH",
        .creation_year = 2016,
        .creation_day = 301,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 208 },
                                    { "LASF_Projection", 34736, 64 },
                                    { "LASF_Projection", 34737, 18 },
                                    { "LASF_Spec", 4, 384 } },
        .listed_vlrs = 4,
        .dims = (const dim_fact[]){ { "Amplitude", 3, 14 }, { "Pulse width", 3, 14 } },
        .dim_count = 2,
        .has_gps_range = true,
        .gps_min = 152900,
        .gps_max = 152900.0001,
        .classes = (const class_fact[]){ { 0, 62 } },
        .class_count = 1,
    },
    {
        .file = "las/gps-time-nan.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.001, 0.001, 0.001 },
        .offset = { 0, 0, 0 },
        .extent_min = { 0, 0, 0 },
        .extent_max = { 0, 0, 0 },
        .extent_is_actual = false,
        .software = "las-rs 0.5.2",
        .system = "las-rs",
        .creation_year = 2017,
        .creation_day = 297,
        .global_encoding = 0,
        .classes = (const class_fact[]){ { 0, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/long-header.las",
        .version_minor = 2,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 1,
        .legacy_point_count = 1,
        .header_size = 229,
        .offset_to_point_data = 440,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 470692.4475, 4602888.905, 16 },
        .extent_max = { 470692.4475, 4602888.905, 16 },
        .extent_is_actual = false,
        .software = "libLAS 1.2",
        .system = "libLAS",
        .creation_year = 2008,
        .creation_day = 78,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 39 } },
        .listed_vlrs = 2,
        .classes = (const class_fact[]){ { 2, 1 } },
        .class_count = 1,
    },
    {
        .file = "las/epsg_4326.las",
        .version_minor = 2,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 5380,
        .legacy_point_count = 5380,
        .header_size = 227,
        .offset_to_point_data = 853,
        .vlr_count = 3,
        .evlr_count = 0,
        .scale = { 1e-07, 1e-07, 1e-07 },
        .offset = { 0, 0, 0 },
        .extent_min = { -94.6834654, 31.0367341, 39.0810002 },
        .extent_max = { -94.6606311, 31.0473291, 78.1190002 },
        .extent_is_actual = false,
        .software = "QT Modeler",
        .system = "MODIFICATION",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34736, 16 },
                                    { "LASF_Projection", 34737, 7 } },
        .listed_vlrs = 3,
        .classes = (const class_fact[]){ { 0, 5380 } },
        .class_count = 1,
    },
    {
        .file = "las/warsaw_small.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 3000,
        .legacy_point_count = 3000,
        .header_size = 227,
        .offset_to_point_data = 284,
        .vlr_count = 1,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 639000, 485000, 0 },
        .extent_min = { 639913.26, 485143.14, 84.7 },
        .extent_max = { 639946.75, 485175.91, 104.55 },
        .extent_is_actual = false,
        .software = "LASzip DLL 3.4 r3 (191111)",
        .system = "",
        .creation_year = 2025,
        .creation_day = 315,
        .global_encoding = 1,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 2112, 3 } },
        .listed_vlrs = 1,
        .wkt_prefix = "''",
        .has_gps_range = true,
        .gps_min = 206860645,
        .gps_max = 206946275.6,
        .classes =
            (const class_fact[]){ { 0, 433 }, { 2, 1381 }, { 3, 257 }, { 4, 27 }, { 5, 902 } },
        .class_count = 5,
    },
    {
        .file = "las/1.2-empty-geotiff-vlrs.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 34,
        .extra_size = 6,
        .point_count = 43,
        .legacy_point_count = 43,
        .header_size = 227,
        .offset_to_point_data = 8398,
        .vlr_count = 5,
        .evlr_count = 0,
        .scale = { 0.00025, 0.00025, 0.00025 },
        .offset = { 34.81025, -28.986, 60.2725 },
        .extent_min = { -25.79175, -15.9695, -13.1125 },
        .extent_max = { 211.08525, 81.46075, 3.28325 },
        .extent_is_actual = false,
        .software = "rdbconvert",
        .system = "EXTRACTION",
        .creation_year = 2016,
        .creation_day = 242,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Spec", 4, 576 },
                                    { "LASF_Projection", 34735, 56 },
                                    { "LASF_Projection", 34736, 0 },
                                    { "LASF_Projection", 34737, 0 },
                                    { "liblas", 7, 7269 } },
        .listed_vlrs = 5,
        .dims = (const dim_fact[]){ { "Amplitude", 3, 14 },
                                    { "Reflectance", 4, 14 },
                                    { "Deviation", 3, 7 } },
        .dim_count = 3,
        .has_gps_range = true,
        .gps_min = 32.3364417,
        .gps_max = 39.711183,
        .classes = (const class_fact[]){ { 0, 43 } },
        .class_count = 1,
    },
    {
        .file = "las/no-points.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 0,
        .legacy_point_count = 0,
        .header_size = 227,
        .offset_to_point_data = 859,
        .vlr_count = 4,
        .evlr_count = 0,
        .scale = { 1e-07, 1e-07, 0.01 },
        .offset = { -127.3906619, 46.80829712, 0 },
        .extent_min = { 0, 0, 0 },
        .extent_max = { 0, 0, 0 },
        .extent_is_actual = false,
        .software = "PDAL 0.1.0",
        .system = "PDAL",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 72 },
                                    { "LASF_Projection", 34736, 40 },
                                    { "LASF_Projection", 34737, 7 },
                                    { "liblas", 2112, 297 } },
        .listed_vlrs = 4,
    },
    {
        .file = "las/mvk-thin.las",
        .version_minor = 2,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 6280,
        .legacy_point_count = 6280,
        .header_size = 227,
        .offset_to_point_data = 3314,
        .vlr_count = 5,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 2045001.76, 1267501.19, 95.79 },
        .extent_max = { 2049993.92, 1272499.79, 228.73 },
        .extent_is_actual = false,
        .software = "GeoCue GeoCoder",
        .system = "NIIRS10",
        .creation_year = 2010,
        .creation_day = 145,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "NIIRS10", 4, 10 },
                                    { "NIIRS10", 1, 26 },
                                    { "LASF_Projection", 34735, 192 },
                                    { "LASF_Projection", 34736, 80 },
                                    { "LASF_Projection", 34737, 101 } },
        .listed_vlrs = 5,
        .has_gps_range = true,
        .gps_min = 338834.4992,
        .gps_max = 340756.3094,
        .classes = (const class_fact[]){ { 1, 129 },
                                         { 2, 1693 },
                                         { 4, 141 },
                                         { 5, 578 },
                                         { 9, 37 },
                                         { 12, 3702 } },
        .class_count = 6,
    },
    {
        .file = "las/sample_c.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 14408,
        .legacy_point_count = 14408,
        .header_size = 227,
        .offset_to_point_data = 227,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 674521.92, 1206740.08, 627.5300293 },
        .extent_min = { 674521.92, 1206740.08, 627.5300293 },
        .extent_max = { 674605.32, 1206814.96, 656.2299805 },
        .extent_is_actual = false,
        .software = "libLAS 1.8.1",
        .system = "libLAS",
        .creation_year = 2018,
        .creation_day = 3,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 159214261.6,
        .gps_max = 159214549.3,
        .classes = (const class_fact[]){ { 2, 1368 },
                                         { 3, 93 },
                                         { 4, 29 },
                                         { 5, 7 },
                                         { 6, 12525 },
                                         { 11, 2 },
                                         { 14, 45 },
                                         { 31, 339 } },
        .class_count = 8,
    },
    {
        .file = "las/test_data_0000_0000_LA93_IGN69_ground.las",
        .version_minor = 2,
        .point_format = 3,
        .record_length = 34,
        .extra_size = 0,
        .point_count = 21172,
        .legacy_point_count = 21172,
        .header_size = 227,
        .offset_to_point_data = 431,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 770500, 6277500, 20.25 },
        .extent_max = { 770550, 6277550, 21.42 },
        .extent_is_actual = false,
        .software = "PDAL 2.4.3 (cd43bf)",
        .system = "PDAL",
        .creation_year = 2023,
        .creation_day = 0,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34737, 32 } },
        .listed_vlrs = 2,
        .has_gps_range = true,
        .gps_min = 306234562,
        .gps_max = 306235309.4,
        .classes = (const class_fact[]){ { 2, 21172 } },
        .class_count = 1,
    },
    {
        .file = "las/malformed_extrabytes.las",
        .version_minor = 2,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 10,
        .legacy_point_count = 10,
        .header_size = 227,
        .offset_to_point_data = 473,
        .vlr_count = 1,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 0, 0, 0 },
        .extent_max = { 9, 9, 0.9 },
        .extent_is_actual = true,
        .software = "pytest",
        .system = "lasRbg",
        .creation_year = 0,
        .creation_day = 0,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Spec", 4, 192 } },
        .listed_vlrs = 1,
        .dims = (const dim_fact[]){ { "TestEB", 3, 0 } },
        .dim_count = 1,
        .classes = (const class_fact[]){ { 2, 10 } },
        .class_count = 1,
    },
    {
        .file = "las/vegetation_1_3.las",
        .version_minor = 3,
        .point_format = 1,
        .record_length = 28,
        .extra_size = 0,
        .point_count = 10683,
        .legacy_point_count = 10683,
        .header_size = 235,
        .offset_to_point_data = 235,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.001, 0.001, 0.001 },
        .offset = { -98436, -55989, -81457 },
        .extent_min = { -98451.205, -55975.417, -81460.091 },
        .extent_max = { -98447.447, -55969.405, -81455.203 },
        .extent_is_actual = false,
        .software = "RS Survey",
        .system = "Siteco Informatica s.r.l.",
        .creation_year = 2017,
        .creation_day = 152,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 552884.8901,
        .gps_max = 552886.4229,
        .classes = (const class_fact[]){ { 11, 10683 } },
        .class_count = 1,
    },
    {
        .file = "las/simple1_3.las",
        .version_minor = 3,
        .point_format = 4,
        .record_length = 57,
        .extra_size = 0,
        .point_count = 999,
        .legacy_point_count = 999,
        .header_size = 235,
        .offset_to_point_data = 5785,
        .vlr_count = 5,
        .evlr_count = 1,
        .scale = { 0.001, 0.001, 0.001 },
        .offset = { 0, 5000000, 0 },
        .extent_min = { -235434.519, 5800843.145, 265.094 },
        .extent_max = { -234935.841, 5800946.249, 273.811 },
        .extent_is_actual = true,
        .software = "ALSXX_PP V2.70 BUILD#15",
        .system = "ALSXX",
        .creation_year = 2010,
        .creation_day = 60,
        .global_encoding = 2,
        .vlrs = (const vlr_fact[]){ { "LeicaGeo", 1001, 5120 },
                                    { "LeicaGeo", 1002, 22 },
                                    { "LeicaGeo", 1003, 54 },
                                    { "LASF_Projection", 34735, 56 },
                                    { "LASF_Spec", 100, 26 } },
        .listed_vlrs = 5,
        .evlrs = (const vlr_fact[]){ { "LAS_Spec", 65535, 100 } },
        .listed_evlrs = 1,
        .has_gps_range = true,
        .gps_min = 129850.0001,
        .gps_max = 129850.0089,
        .classes = (const class_fact[]){ { 1, 999 } },
        .class_count = 1,
    },
    {
        .file = "las/no-points-1.3.las",
        .version_minor = 3,
        .point_format = 0,
        .record_length = 20,
        .extra_size = 0,
        .point_count = 0,
        .legacy_point_count = 0,
        .header_size = 235,
        .offset_to_point_data = 235,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 1, 1, 1 },
        .offset = { 0, 0, 0 },
        .extent_min = { 0, 0, 0 },
        .extent_max = { 0, 0, 0 },
        .extent_is_actual = false,
        .software = "LASzip DLL 3.4 r3 (191111)",
        .system = "",
        .creation_year = 2023,
        .creation_day = 200,
        .global_encoding = 0,
    },
    {
        .file = "las/test1_4.las",
        .version_minor = 4,
        .point_format = 6,
        .record_length = 30,
        .extra_size = 0,
        .point_count = 1000,
        .legacy_point_count = 1000,
        .header_size = 375,
        .offset_to_point_data = 2305,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 1.16451354e-06, 1.164510015e-06, 1.003143236e-06 },
        .offset = { 1692500.352, 1817499.596, 7350.194653 },
        .extent_min = { 1694038.446, 1816492.706, 5592.749917 },
        .extent_max = { 1694539.677, 1816497.976, 5599.069686 },
        .extent_is_actual = false,
        .software = "Global Mapper",
        .system = "",
        .creation_year = 2014,
        .creation_day = 344,
        .global_encoding = 17,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 2112, 911 }, { "liblas", 2112, 911 } },
        .listed_vlrs = 2,
        .wkt_prefix = "PROJCS[\"NAD83(HARN) / New Mexico Central (ftUS)\"",
        .has_gps_range = true,
        .gps_min = 83177420.53,
        .gps_max = 83177420.6,
        .classes = (const class_fact[]){ { 2, 1000 } },
        .class_count = 1,
    },
    {
        .file = "las/1_4_w_evlr.las",
        .version_minor = 4,
        .point_format = 6,
        .record_length = 30,
        .extra_size = 0,
        .point_count = 1000,
        .legacy_point_count = 0,
        .header_size = 375,
        .offset_to_point_data = 2305,
        .vlr_count = 2,
        .evlr_count = 1,
        .scale = { 1.16451354e-06, 1.164510015e-06, 1.003143236e-06 },
        .offset = { 1692500.352, 1817499.596, 7350.194653 },
        .extent_min = { 1694038.446, 1816492.706, 5592.749917 },
        .extent_max = { 1694539.677, 1816497.976, 5599.069687 },
        .extent_is_actual = false,
        .software = "pylas",
        .system = "",
        .creation_year = 2021,
        .creation_day = 153,
        .global_encoding = 17,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 2112, 911 }, { "liblas", 2112, 911 } },
        .listed_vlrs = 2,
        .evlrs = (const vlr_fact[]){ { "pylastest", 42, 16 } },
        .listed_evlrs = 1,
        .wkt_prefix = "PROJCS[\"NAD83(HARN) / New Mexico Central (ftUS)\"",
        .has_gps_range = true,
        .gps_min = 83177420.53,
        .gps_max = 83177420.6,
        .classes = (const class_fact[]){ { 2, 1000 } },
        .class_count = 1,
    },
    {
        .file = "las/simple1_4.las",
        .version_minor = 4,
        .point_format = 7,
        .record_length = 36,
        .extra_size = 0,
        .point_count = 22600,
        .legacy_point_count = 22600,
        .header_size = 375,
        .offset_to_point_data = 571,
        .vlr_count = 2,
        .evlr_count = 1,
        .scale = { 1e-06, 1e-07, 0.001 },
        .offset = { 1, 1, 0 },
        .extent_min = { 1, 1, 44 },
        .extent_max = { 226, 100, 254 },
        .extent_is_actual = false,
        .software = "Global Mapper",
        .system = "",
        .creation_year = 2012,
        .creation_day = 13,
        .global_encoding = 0,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 34735, 64 },
                                    { "LASF_Projection", 34736, 24 } },
        .listed_vlrs = 2,
        .evlrs = (const vlr_fact[]){ { "LASF_Projection", 2112, 157 } },
        .listed_evlrs = 1,
        .wkt_prefix = "GEOGCS[\"Geographic Coordinate System\"",
        .has_gps_range = true,
        .gps_min = 0,
        .gps_max = 0,
        .classes = (const class_fact[]){ { 0, 22600 } },
        .class_count = 1,
    },
    {
        .file = "las/unregistered_extra_bytes.las",
        .version_minor = 4,
        .point_format = 6,
        .record_length = 34,
        .extra_size = 4,
        .point_count = 4,
        .legacy_point_count = 0,
        .header_size = 375,
        .offset_to_point_data = 375,
        .vlr_count = 0,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 1, 1, 1 },
        .extent_max = { 4, 4, 4 },
        .extent_is_actual = false,
        .software = "laspy 2.0.2",
        .system = "OTHER",
        .creation_year = 2021,
        .creation_day = 235,
        .global_encoding = 0,
        .has_gps_range = true,
        .gps_min = 0,
        .gps_max = 0,
        .classes = (const class_fact[]){ { 0, 4 } },
        .class_count = 1,
    },
    {
        .file = "las/5points_14.las",
        .version_minor = 4,
        .point_format = 6,
        .record_length = 33,
        .extra_size = 3,
        .point_count = 5,
        .legacy_point_count = 0,
        .header_size = 375,
        .offset_to_point_data = 921,
        .vlr_count = 3,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 600000, 4800000, 0 },
        .extent_min = { 630498.56, 4834748.73, 62.15 },
        .extent_max = { 630499.95, 4834749.66, 63.68 },
        .extent_is_actual = true,
        .software = "LASzip DLL 2.4 r1 (150905)",
        .system = "LASzip DLL example 9",
        .creation_year = 2015,
        .creation_day = 30,
        .global_encoding = 17,
        .vlrs = (const vlr_fact[]){ { "LASF_Spec", 4, 384 },
                                    { "LASF_Projection", 2112, 0 },
                                    { "funny", 12345, 0 } },
        .listed_vlrs = 3,
        .wkt_prefix = "",
        .dims = (const dim_fact[]){ { "height above ground", 4, 24 }, { "coverage count", 1, 24 } },
        .dim_count = 2,
        .has_gps_range = true,
        .gps_min = 53413162.56,
        .gps_max = 53413162.58,
        .classes = (const class_fact[]){ { 2, 2 }, { 5, 1 }, { 41, 1 }, { 42, 1 } },
        .class_count = 4,
    },
    {
        .file = "las/autzen-bmx-2010.las",
        .version_minor = 4,
        .point_format = 7,
        .record_length = 36,
        .extra_size = 0,
        .point_count = 829,
        .legacy_point_count = 0,
        .header_size = 375,
        .offset_to_point_data = 1270,
        .vlr_count = 1,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 194000, 259000, 0 },
        .extent_min = { 194472.82, 259222.19, 422.93 },
        .extent_max = { 194506.92, 259264.09, 434.51 },
        .extent_is_actual = false,
        .software = "LASzip DLL 3.4 r3 (191111)",
        .system = "",
        .creation_year = 2025,
        .creation_day = 339,
        .global_encoding = 16,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 2112, 841 } },
        .listed_vlrs = 1,
        .wkt_prefix = "COMPD_CS[\"NAD83 / Oregon LCC (m) + NAVD88 height (ftUS)\"",
        .has_gps_range = true,
        .gps_min = 246493.4781,
        .gps_max = 247190.8903,
        .classes = (const class_fact[]){ { 2, 829 } },
        .class_count = 1,
    },
    {
        .file = "las/gib_las_col.las",
        .version_minor = 4,
        .point_format = 8,
        .record_length = 38,
        .extra_size = 0,
        .point_count = 6236,
        .legacy_point_count = 0,
        .header_size = 375,
        .offset_to_point_data = 1847,
        .vlr_count = 2,
        .evlr_count = 0,
        .scale = { 0.01, 0.01, 0.01 },
        .offset = { 0, 0, 0 },
        .extent_min = { 484269.74, 6484000.41, 83.09 },
        .extent_max = { 484999.97, 6484999.96, 153.39 },
        .extent_is_actual = false,
        .software = "PDAL 2.6.3 (Releas)",
        .system = "PDAL",
        .creation_year = 2025,
        .creation_day = 14,
        .global_encoding = 16,
        .vlrs = (const vlr_fact[]){ { "LASF_Projection", 2112, 682 }, { "liblas", 2112, 682 } },
        .listed_vlrs = 2,
        .wkt_prefix = "PROJCS[\"RGF93 v1 / Lambert-93\"",
        .has_gps_range = true,
        .gps_min = 316447635.3,
        .gps_max = 316449293.8,
        .classes = (const class_fact[]){ { 1, 6236 } },
        .class_count = 1,
    },
};

/* ---- helpers ------------------------------------------------------------------ */

static const las_fact *find_fact(const char *file)
{
    for (size_t i = 0; i < sizeof(corpus_facts) / sizeof(corpus_facts[0]); i++) {
        if (strcmp(corpus_facts[i].file, file) == 0) {
            return &corpus_facts[i];
        }
    }
    fail_msg("no README facts for %s", file);
    return NULL;
}

// Relative comparison for numbers the README prints with 10 significant digits.
static void assert_close(double actual, double expected, double tolerance, const char *what,
                         const char *file)
{
    if (!(fabs(actual - expected) <= tolerance)) {
        fail_msg("%s: %s is %.12g, README says %.12g (tolerance %g)", file, what, actual, expected,
                 tolerance);
    }
}

static double readme_rounding(double value)
{
    return 1e-9 * fmax(fabs(value), 1.0);
}

static bool has_prefix(const char *text, const char *prefix)
{
    return strncmp(text, prefix, strlen(prefix)) == 0;
}

static bool contains(const char *text, const char *needle)
{
    return strstr(text, needle) != NULL;
}

// What the LAS 1.4 specification says each point format carries.
static uint32_t expected_attributes(int format)
{
    static const bool gps[11] = { 0, 1, 0, 1, 1, 1, 1, 1, 1, 1, 1 };
    static const bool rgb[11] = { 0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 1 };
    static const bool nir[11] = { 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1 };
    static const bool wave[11] = { 0, 0, 0, 0, 1, 1, 0, 0, 0, 1, 1 };
    uint32_t bits = STA_ATTR_INTENSITY | STA_ATTR_RETURNS | STA_ATTR_CLASSIFICATION |
                    STA_ATTR_SCAN_ANGLE | STA_ATTR_USER_DATA | STA_ATTR_POINT_SOURCE_ID |
                    STA_ATTR_SCAN_FLAGS;
    bits |= gps[format] ? STA_ATTR_GPS_TIME : 0u;
    bits |= rgb[format] ? STA_ATTR_RGB : 0u;
    bits |= nir[format] ? STA_ATTR_NIR : 0u;
    bits |= wave[format] ? STA_ATTR_WAVE_PACKET : 0u;
    bits |= format >= 6 ? STA_ATTR_SCANNER_CHANNEL : 0u;
    return bits;
}

typedef struct scan_result {
    unsigned long long count;
    double min[3], max[3];
    double gps_min, gps_max;
    unsigned long long gps_nan;
    unsigned long long class_counts[256];
    uint64_t middle_index;
    sta_point middle; /* the point at middle_index */
} scan_result;

// Reads every point in batches of `capacity`, checking batch indices as it goes.
static void scan_points(sta_cloud_reader *reader, size_t capacity, scan_result *out)
{
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    memset(out, 0, sizeof(*out));
    for (int axis = 0; axis < 3; axis++) {
        out->min[axis] = HUGE_VAL;
        out->max[axis] = -HUGE_VAL;
    }
    out->gps_min = HUGE_VAL;
    out->gps_max = -HUGE_VAL;
    out->middle_index = info->point_count / 2;

    sta_point_batch batch = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_point_batch_init(&batch, capacity, info->extra_size, &err), STA_OK);
    for (;;) {
        sta_status status = sta_cloud_read(reader, &batch, &err);
        if (status != STA_OK) {
            fail_msg("%s: read failed: %s", info->path, err.message);
        }
        if (batch.count == 0) {
            break;
        }
        assert_int_equal(batch.first_index, out->count);
        for (size_t i = 0; i < batch.count; i++) {
            const sta_point *p = &batch.points[i];
            int32_t xyz[3] = { p->X, p->Y, p->Z };
            for (int axis = 0; axis < 3; axis++) {
                double v = sta_grid_apply(&info->grid, axis, xyz[axis]);
                out->min[axis] = fmin(out->min[axis], v);
                out->max[axis] = fmax(out->max[axis], v);
            }
            if (isnan(p->gps_time)) {
                out->gps_nan++;
            } else {
                out->gps_min = fmin(out->gps_min, p->gps_time);
                out->gps_max = fmax(out->gps_max, p->gps_time);
            }
            out->class_counts[p->classification]++;
            if (out->count + i == out->middle_index) {
                out->middle = *p;
            }
        }
        out->count += batch.count;
    }
    sta_point_batch_release(&batch);
}

static void check_extent(const scan_result *scan, const double *min, const double *max,
                         const sta_grid *grid, double steps, const char *file)
{
    static const char *const names[3] = { "min x", "min y", "min z" };
    static const char *const max_names[3] = { "max x", "max y", "max z" };
    for (int axis = 0; axis < 3; axis++) {
        double step = steps * grid->scale[axis];
        assert_close(scan->min[axis], min[axis], step + readme_rounding(min[axis]), names[axis],
                     file);
        assert_close(scan->max[axis], max[axis], step + readme_rounding(max[axis]), max_names[axis],
                     file);
    }
}

static void check_vlr(const sta_vlr_info *vlr, const vlr_fact *fact, bool extended,
                      const char *file)
{
    if (strcmp(vlr->user_id, fact->user_id) != 0 || vlr->record_id != fact->record_id ||
        vlr->length != fact->length || vlr->is_extended != extended) {
        fail_msg("%s: record %s/%u (%llu B, extended %d), README says %s/%u (%llu B)", file,
                 vlr->user_id, vlr->record_id, (unsigned long long)vlr->length, vlr->is_extended,
                 fact->user_id, fact->record_id, fact->length);
    }
}

static void check_header_facts(const sta_cloud_info *info, const las_fact *f)
{
    const char *file = f->file;
    assert_int_equal(info->kind, STA_CLOUD_LAS);
    assert_int_equal(info->version_major, 1);
    assert_int_equal(info->version_minor, f->version_minor);
    assert_int_equal(info->point_format, f->point_format);
    assert_int_equal(info->record_length, f->record_length);
    assert_int_equal(info->extra_size, f->extra_size);
    assert_int_equal(info->header_size, f->header_size);
    assert_int_equal(info->offset_to_point_data, f->offset_to_point_data);
    assert_int_equal(info->point_count, f->point_count);
    assert_int_equal(info->header_point_count, f->point_count);
    assert_int_equal(info->legacy_point_count, f->legacy_point_count);
    assert_int_equal(info->skipped_point_count, 0);
    for (int axis = 0; axis < 3; axis++) {
        assert_close(info->grid.scale[axis], f->scale[axis],
                     readme_rounding(f->scale[axis]) * f->scale[axis], "scale", file);
        assert_close(info->grid.offset[axis], f->offset[axis], readme_rounding(f->offset[axis]),
                     "offset", file);
    }
    assert_string_equal(info->generating_software, f->software);
    assert_string_equal(info->system_identifier, f->system);
    assert_int_equal(info->creation_year, f->creation_year);
    assert_int_equal(info->creation_day, f->creation_day);
    assert_int_equal(info->global_encoding, f->global_encoding);
    assert_int_equal(info->has_internal_waveform, (f->global_encoding & 2) != 0);
    assert_int_equal(info->attributes, expected_attributes(f->point_format));
    int pf = f->point_format;
    assert_int_equal(info->has_waveform_packets, pf == 4 || pf == 5 || pf == 9 || pf == 10);

    size_t vlrs = 0, evlrs = 0;
    for (size_t i = 0; i < info->vlr_count; i++) {
        // VLRs first, then EVLRs.
        if (info->vlrs[i].is_extended) {
            evlrs++;
        } else {
            assert_int_equal(evlrs, 0);
            vlrs++;
        }
    }
    assert_int_equal(vlrs, f->vlr_count);
    assert_int_equal(evlrs, f->evlr_count);
    assert_true(f->listed_vlrs <= vlrs);
    for (size_t i = 0; i < f->listed_vlrs; i++) {
        check_vlr(&info->vlrs[i], &f->vlrs[i], false, file);
    }
    assert_int_equal(f->listed_evlrs, evlrs);
    for (size_t i = 0; i < f->listed_evlrs; i++) {
        check_vlr(&info->vlrs[vlrs + i], &f->evlrs[i], true, file);
    }
    if (f->listed_vlrs == vlrs) {
        bool geotiff = false;
        for (size_t i = 0; i < f->listed_vlrs; i++) {
            geotiff |=
                strcmp(f->vlrs[i].user_id, "LASF_Projection") == 0 && f->vlrs[i].record_id == 34735;
        }
        assert_int_equal(info->has_geotiff_crs, geotiff);
    }

    if (!f->wkt_prefix) {
        assert_null(info->crs_wkt);
    } else if (strlen(f->wkt_prefix) <= 2) {
        // The README shows short WKTs whole: "(empty string)" and "''".
        assert_non_null(info->crs_wkt);
        assert_string_equal(info->crs_wkt, f->wkt_prefix);
    } else {
        assert_non_null(info->crs_wkt);
        if (!has_prefix(info->crs_wkt, f->wkt_prefix)) {
            fail_msg("%s: WKT starts \"%.60s\", README says \"%s\"", file, info->crs_wkt,
                     f->wkt_prefix);
        }
    }
}

static void check_extra_dims(const sta_cloud_info *info, const las_fact *f)
{
    size_t declared = 0;
    assert_true(info->extra_dim_count >= f->dim_count);
    for (size_t i = 0; i < f->dim_count; i++) {
        const sta_extra_dim *dim = &info->extra_dims[i];
        assert_string_equal(dim->name, f->dims[i].name);
        assert_int_equal(dim->data_type, f->dims[i].data_type);
        assert_int_equal(dim->options, f->dims[i].options);
        assert_int_equal(dim->offset_bytes, declared);
        declared += dim->size_bytes;
    }
    assert_true(declared <= f->extra_size);
    if (declared < f->extra_size) {
        // The rest of each record is described as one opaque run.
        assert_int_equal(info->extra_dim_count, f->dim_count + 1);
        const sta_extra_dim *tail = &info->extra_dims[f->dim_count];
        assert_string_equal(tail->name, "undeclared");
        assert_int_equal(tail->data_type, 0);
        assert_int_equal(tail->offset_bytes, declared);
        assert_int_equal(tail->size_bytes, f->extra_size - declared);
    } else {
        assert_int_equal(info->extra_dim_count, f->dim_count);
    }
}

static void check_points(sta_cloud_reader *reader, const las_fact *f)
{
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    scan_result scan;
    scan_points(reader, 1000, &scan);
    assert_int_equal(scan.count, f->point_count);
    if (f->point_count > 0) {
        check_extent(&scan, f->extent_min, f->extent_max, &info->grid,
                     f->extent_is_actual ? 0.5 : 1.0, f->file);
    }
    if (f->has_gps_range) {
        assert_int_equal(scan.gps_nan, 0);
        assert_close(scan.gps_min, f->gps_min, readme_rounding(f->gps_min), "GPS min", f->file);
        assert_close(scan.gps_max, f->gps_max, readme_rounding(f->gps_max), "GPS max", f->file);
    }
    unsigned long long listed = 0;
    for (size_t i = 0; i < f->class_count; i++) {
        if (scan.class_counts[f->classes[i].classification] != f->classes[i].count) {
            fail_msg("%s: %llu points of class %u, README says %llu", f->file,
                     scan.class_counts[f->classes[i].classification], f->classes[i].classification,
                     f->classes[i].count);
        }
        listed += f->classes[i].count;
    }
    assert_int_equal(listed, f->point_count);

    // Seeking to the middle yields the same point as the sequential read.
    if (f->point_count > 0) {
        sta_error err = { 0 };
        assert_int_equal(sta_cloud_seek(reader, scan.middle_index, &err), STA_OK);
        sta_point_batch batch = { 0 };
        assert_int_equal(sta_point_batch_init(&batch, 7, info->extra_size, &err), STA_OK);
        assert_int_equal(sta_cloud_read(reader, &batch, &err), STA_OK);
        assert_true(batch.count >= 1);
        assert_int_equal(batch.first_index, scan.middle_index);
        assert_memory_equal(&batch.points[0], &scan.middle, sizeof(sta_point));
        sta_point_batch_release(&batch);
    }
}

// sta_cloud_read_positions gives the X, Y, Z of sta_cloud_read, batch by batch, and
// leaves the other fields alone.
static void check_positions_only(sta_cloud_reader *reader)
{
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    sta_error err = { 0 };
    sta_point_batch full = { 0 }, xyz = { 0 };
    assert_int_equal(sta_point_batch_init(&full, 333, info->extra_size, &err), STA_OK);
    assert_int_equal(sta_point_batch_init(&xyz, 333, info->extra_size, &err), STA_OK);
    size_t length = strlen(info->path);
    bool laz = length >= 4 && strcmp(info->path + length - 4, ".laz") == 0; // whole records
    uint64_t seen = 0;
    for (;;) {
        assert_int_equal(sta_cloud_seek(reader, seen, &err), STA_OK);
        assert_int_equal(sta_cloud_read(reader, &full, &err), STA_OK);
        assert_int_equal(sta_cloud_seek(reader, seen, &err), STA_OK);
        for (size_t i = 0; i < xyz.capacity; i++) {
            xyz.points[i].intensity = 0xBEEF; // must survive
        }
        assert_int_equal(sta_cloud_read_positions(reader, &xyz, &err), STA_OK);
        assert_int_equal(xyz.count, full.count);
        assert_int_equal(xyz.first_index, full.first_index);
        for (size_t i = 0; i < full.count; i++) {
            if (xyz.points[i].X != full.points[i].X || xyz.points[i].Y != full.points[i].Y ||
                xyz.points[i].Z != full.points[i].Z) {
                fail_msg("%s: point %llu: positions-only read differs", info->path,
                         (unsigned long long)(seen + i));
            }
            if (!laz) {
                assert_int_equal(xyz.points[i].intensity, 0xBEEF);
            }
        }
        if (full.count == 0) {
            break;
        }
        seen += full.count;
    }
    assert_int_equal(seen, info->point_count);
    sta_point_batch_release(&full);
    sta_point_batch_release(&xyz);
}

static void check_corpus_file(const char *file)
{
    const las_fact *f = find_fact(file);
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    if (sta_cloud_open(sta_test_shared_path(file), NULL, &reader, &err) != STA_OK) {
        fail_msg("%s: %s", file, err.message);
    }
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    check_header_facts(info, f);
    if (strcmp(file, "las/malformed_extrabytes.las") != 0) {
        check_extra_dims(info, f); // malformed_extrabytes has its own case
    }
    check_points(reader, f);
    check_positions_only(reader);
    sta_cloud_close(reader);
}

#define CORPUS_TEST(name, file)                                                                    \
 static void name(void **state)                                                                    \
 {                                                                                                 \
  (void)state;                                                                                     \
  STA_TEST_REQUIRE_SHARED_DATA();                                                                  \
  check_corpus_file(file);                                                                         \
 }

CORPUS_TEST(file_liblas_1_0_0, "las/liblas_1.0_0.las")
CORPUS_TEST(file_liblas_1_0_1, "las/liblas_1.0_1.las")
CORPUS_TEST(file_TO_core_last_clip, "las/TO_core_last_clip.las")
CORPUS_TEST(file_point10_1_0, "las/point10-1.0.las")
CORPUS_TEST(file_Example, "las/Example.las")
CORPUS_TEST(file_liblas_1_1_0, "las/liblas_1.1_0.las")
CORPUS_TEST(file_liblas_1_1_1, "las/liblas_1.1_1.las")
CORPUS_TEST(file_simple1_1, "las/simple1_1.las")
CORPUS_TEST(file_lots_of_vlr, "las/lots_of_vlr.las")
CORPUS_TEST(file_liblas_1_2_0, "las/liblas_1.2_0.las")
CORPUS_TEST(file_liblas_1_2_1, "las/liblas_1.2_1.las")
CORPUS_TEST(file_liblas_1_2_2, "las/liblas_1.2_2.las")
CORPUS_TEST(file_liblas_1_2_3, "las/liblas_1.2_3.las")
CORPUS_TEST(file_point10, "las/point10.las")
CORPUS_TEST(file_point_time, "las/point-time.las")
CORPUS_TEST(file_point_color, "las/point-color.las")
CORPUS_TEST(file_point_time_color, "las/point-time-color.las")
CORPUS_TEST(file_extra_bytes, "las/extra-bytes.las")
CORPUS_TEST(file_simple, "las/simple.las")
CORPUS_TEST(file_autzen_trim, "las/autzen_trim.las")
CORPUS_TEST(file_autzen_point_format_3, "las/autzen-point-format-3.las")
CORPUS_TEST(file_1815, "las/1815.las")
CORPUS_TEST(file_Megaplot, "las/Megaplot.las")
CORPUS_TEST(file_MixedConifer, "las/MixedConifer.las")
CORPUS_TEST(file_extra_byte, "las/extra_byte.las")
CORPUS_TEST(file_gps_time_nan, "las/gps-time-nan.las")
CORPUS_TEST(file_long_header, "las/long-header.las")
CORPUS_TEST(file_epsg_4326, "las/epsg_4326.las")
CORPUS_TEST(file_warsaw_small, "las/warsaw_small.las")
CORPUS_TEST(file_1_2_empty_geotiff_vlrs, "las/1.2-empty-geotiff-vlrs.las")
CORPUS_TEST(file_no_points, "las/no-points.las")
CORPUS_TEST(file_mvk_thin, "las/mvk-thin.las")
CORPUS_TEST(file_sample_c, "las/sample_c.las")
CORPUS_TEST(file_test_data_0000_0000_LA93_IGN69_ground,
            "las/test_data_0000_0000_LA93_IGN69_ground.las")
CORPUS_TEST(file_malformed_extrabytes, "las/malformed_extrabytes.las")
CORPUS_TEST(file_vegetation_1_3, "las/vegetation_1_3.las")
CORPUS_TEST(file_simple1_3, "las/simple1_3.las")
CORPUS_TEST(file_no_points_1_3, "las/no-points-1.3.las")
CORPUS_TEST(file_test1_4, "las/test1_4.las")
CORPUS_TEST(file_1_4_w_evlr, "las/1_4_w_evlr.las")
CORPUS_TEST(file_simple1_4, "las/simple1_4.las")
CORPUS_TEST(file_unregistered_extra_bytes, "las/unregistered_extra_bytes.las")
CORPUS_TEST(file_5points_14, "las/5points_14.las")
CORPUS_TEST(file_autzen_bmx_2010, "las/autzen-bmx-2010.las")
CORPUS_TEST(file_gib_las_col, "las/gib_las_col.las")

/* ---- files broken by design ----------------------------------------------------- */

static void clipped_file_is_an_error_by_default(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    sta_status status =
        sta_cloud_open(sta_test_shared_path("las/1.2-with-color-clipped.las"), NULL, &reader, &err);
    assert_int_equal(status, STA_ERR_FORMAT);
    assert_null(reader);
    // README: header says 1065 points, only 1064 complete records are present.
    assert_true(contains(err.message, "1.2-with-color-clipped.las"));
    assert_true(contains(err.message, "point count 1065"));
    assert_true(contains(err.message, "1064 complete records"));
}

static void clipped_file_salvages_1064_points(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    sta_read_options options = { .salvage_truncated = true };
    sta_status status = sta_cloud_open(sta_test_shared_path("las/1.2-with-color-clipped.las"),
                                       &options, &reader, &err);
    if (status != STA_OK) {
        fail_msg("%s", err.message);
    }
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    assert_int_equal(info->point_count, 1064);
    assert_int_equal(info->header_point_count, 1065);
    assert_int_equal(info->skipped_point_count, 1);
    assert_int_equal(info->offset_to_point_data, 229);
    assert_int_equal(info->point_format, 3);
    scan_result scan;
    scan_points(reader, 100, &scan);
    assert_int_equal(scan.count, 1064);
    // README: classes 1:788, 2:276 over the complete records.
    assert_int_equal(scan.class_counts[1], 788);
    assert_int_equal(scan.class_counts[2], 276);
    const double min[3] = { 635619.85, 848899.7, 406.59 };
    const double max[3] = { 638982.55, 853535.43, 586.38 };
    check_extent(&scan, min, max, &info->grid, 1.0, "las/1.2-with-color-clipped.las");
    assert_true(scan.gps_min >= 245370.4171 - 1e-3 && scan.gps_max <= 249783.1622 + 1e-3);
    sta_cloud_close(reader);
}

/* Decision (see src/io/las_vlr.c): a VLR count that overshoots is an error; with
 * salvage the points are read from offset_to_point_data (the fuzzed header says
 * 1069128089 VLRs; its point data is 6 bytes short of 719 records: 718 whole). */
static void garbage_vlr_count_is_salvaged(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    sta_log_set_level(STA_LOG_QUIET);
    for (int salvage = 0; salvage <= 1; salvage++) {
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        sta_read_options options = { .salvage_truncated = salvage != 0 };
        sta_status status = sta_cloud_open(sta_test_shared_path("las/garbage_nVariableLength.las"),
                                           &options, &reader, &err);
        if (!salvage) {
            assert_int_equal(status, STA_ERR_FORMAT);
            assert_null(reader);
            assert_true(contains(err.message, "garbage_nVariableLength.las"));
            assert_true(contains(err.message, "number of VLRs 1069128089"));
            continue;
        }
        if (status != STA_OK) {
            fail_msg("salvage: %s", err.message);
        }
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(info->vlr_count, 0);
        assert_int_equal(info->point_count, 718);
        assert_int_equal(info->skipped_point_count, 1);
        scan_result scan;
        scan_points(reader, 100, &scan);
        assert_int_equal(scan.count, 718);
        sta_cloud_close(reader);
    }
    sta_log_set_level(STA_LOG_WARN);
}

/* Decision (see src/io/las_extra.c): an Extra Bytes descriptor that does not fit the
 * records is ignored with a warning; the points are read as they are. */
static void malformed_extra_bytes_descriptor_is_ignored(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    sta_status status =
        sta_cloud_open(sta_test_shared_path("las/malformed_extrabytes.las"), NULL, &reader, &err);
    if (status != STA_OK) {
        fail_msg("%s", err.message);
    }
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    assert_int_equal(info->record_length, 20);
    assert_int_equal(info->extra_size, 0);
    assert_int_equal(info->extra_dim_count, 0);
    assert_null(info->extra_dims);
    // The VLR itself is still listed.
    assert_int_equal(info->vlr_count, 1);
    assert_string_equal(info->vlrs[0].user_id, "LASF_Spec");
    assert_int_equal(info->vlrs[0].record_id, 4);
    assert_int_equal(info->vlrs[0].length, 192);
    scan_result scan;
    scan_points(reader, 1000, &scan);
    assert_int_equal(scan.count, 10);
    const double min[3] = { 0, 0, 0 };
    const double max[3] = { 9, 9, 0.9 };
    check_extent(&scan, min, max, &info->grid, 0.5, "las/malformed_extrabytes.las");
    sta_cloud_close(reader);
}

/* The point14 (PDRF 6) LAZ file read through the ordinary reader gives the same points as
 * its LAS twin: count, extent, GPS range and classes. */
static void laz_point14_reads_like_its_twin(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    const char *files[2] = { "laz/1_4_w_evlr.laz", "las/1_4_w_evlr.las" };
    scan_result scans[2];
    for (size_t i = 0; i < 2; i++) {
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        if (sta_cloud_open(sta_test_shared_path(files[i]), NULL, &reader, &err) != STA_OK) {
            fail_msg("%s: %s", files[i], err.message);
        }
        assert_int_equal(sta_cloud_reader_info(reader)->point_format, 6);
        scan_points(reader, 77, &scans[i]);
        sta_cloud_close(reader);
    }
    assert_int_equal(scans[0].count, 1000);
    assert_int_equal(scans[0].count, scans[1].count);
    for (int axis = 0; axis < 3; axis++) {
        assert_true(scans[0].min[axis] == scans[1].min[axis]);
        assert_true(scans[0].max[axis] == scans[1].max[axis]);
    }
    assert_true(scans[0].gps_min == scans[1].gps_min && scans[0].gps_max == scans[1].gps_max);
    assert_memory_equal(scans[0].class_counts, scans[1].class_counts,
                        sizeof(scans[0].class_counts));
}

// Every *.las file in las/ has README facts or a case of its own.
static void corpus_table_covers_every_file(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const char *const special[] = { "1.2-with-color-clipped.las",
                                           "garbage_nVariableLength.las" };
    DIR *dir = opendir(sta_test_shared_path("las"));
    assert_non_null(dir);
    struct dirent *entry;
    size_t files = 0;
    char name[300];
    while ((entry = readdir(dir)) != NULL) {
        size_t length = strlen(entry->d_name);
        if (length < 4 || strcmp(entry->d_name + length - 4, ".las") != 0) {
            continue;
        }
        files++;
        bool known = false;
        for (size_t i = 0; i < 2; i++) {
            known |= strcmp(entry->d_name, special[i]) == 0;
        }
        snprintf(name, sizeof(name), "las/%s", entry->d_name);
        for (size_t i = 0; i < sizeof(corpus_facts) / sizeof(corpus_facts[0]); i++) {
            known |= strcmp(corpus_facts[i].file, name) == 0;
        }
        if (!known) {
            fail_msg("%s has no test", name);
        }
    }
    closedir(dir);
    assert_int_equal(files, sizeof(corpus_facts) / sizeof(corpus_facts[0]) + 2);
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

// README: 200 files, LAS 1.2 PDRF 2, scale 0.001, offset 0, no VLRs, 341989 points in
// total, union of actual extents min (-4.985, 1.039, -3.445) max (-0.789, 6.724, 1.124).
static void lion_200_files_sum_to_341989(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char folder[4096];
    snprintf(folder, sizeof(folder), "%s", sta_test_shared_path("las/potree_lion_takanawa"));
    DIR *dir = opendir(folder);
    assert_non_null(dir);
    char *names[256];
    size_t count = 0;
    struct dirent *entry;
    while ((entry = readdir(dir)) != NULL) {
        size_t length = strlen(entry->d_name);
        if (length >= 4 && strcmp(entry->d_name + length - 4, ".las") == 0) {
            assert_true(count < 256);
            names[count++] = strdup(entry->d_name);
        }
    }
    closedir(dir);
    assert_int_equal(count, 200);
    qsort(names, count, sizeof(names[0]), compare_names);

    unsigned long long total = 0;
    double min[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL };
    double max[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    sta_grid grid;
    memset(&grid, 0, sizeof(grid));
    for (size_t i = 0; i < count; i++) {
        char path[4400];
        snprintf(path, sizeof(path), "%s/%s", folder, names[i]);
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        if (sta_cloud_open(path, NULL, &reader, &err) != STA_OK) {
            fail_msg("%s", err.message);
        }
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(info->version_minor, 2);
        assert_int_equal(info->point_format, 2);
        assert_int_equal(info->record_length, 26);
        assert_int_equal(info->vlr_count, 0);
        for (int axis = 0; axis < 3; axis++) {
            assert_true(info->grid.scale[axis] == 0.001 && info->grid.offset[axis] == 0.0);
        }
        grid = info->grid;
        scan_result scan;
        scan_points(reader, 4096, &scan);
        assert_int_equal(scan.count, info->point_count);
        assert_true(scan.count >= 1 && scan.count <= 8450);
        total += scan.count;
        for (int axis = 0; axis < 3; axis++) {
            min[axis] = fmin(min[axis], scan.min[axis]);
            max[axis] = fmax(max[axis], scan.max[axis]);
        }
        sta_cloud_close(reader);
        free(names[i]);
    }
    assert_int_equal(total, 341989);
    scan_result all = { 0 };
    memcpy(all.min, min, sizeof(min));
    memcpy(all.max, max, sizeof(max));
    const double readme_min[3] = { -4.985, 1.039, -3.445 };
    const double readme_max[3] = { -0.789, 6.724, 1.124 };
    check_extent(&all, readme_min, readme_max, &grid, 0.5, "las/potree_lion_takanawa");
}

/* ---- an independent decoder and encoder (LAS 1.4 R15, tables 7-17) --------------- */

typedef struct ref_point {
    long long X, Y, Z;
    unsigned intensity, return_number, number_of_returns, scan_direction, edge;
    unsigned classification, flags, channel, user_data, point_source_id;
    int scan_angle_raw; /* as stored: degrees (formats 0-5) or 0.006 degree (6-10) */
    double gps_time;
    unsigned red, green, blue, nir;
    unsigned wave_index;
    unsigned long long wave_offset;
    unsigned wave_size;
    float wave_location, wave_xt, wave_yt, wave_zt;
} ref_point;

static const unsigned spec_sizes[11] = { 20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67 };

static unsigned long long get_le(const uint8_t *p, int bytes)
{
    unsigned long long v = 0;
    for (int i = bytes - 1; i >= 0; i--) {
        v = v * 256u + p[i];
    }
    return v;
}

static long long get_signed(const uint8_t *p, int bytes)
{
    unsigned long long v = get_le(p, bytes);
    unsigned long long half = 1ull << (8 * bytes - 1);
    return v >= half ? (long long)(v - half) - (long long)half : (long long)v;
}

static void put_le(uint8_t *p, unsigned long long v, int bytes)
{
    for (int i = 0; i < bytes; i++) {
        p[i] = (uint8_t)(v >> (8 * i));
    }
}

static bool format_has(int format, const char *what)
{
    if (strcmp(what, "gps") == 0) {
        return format == 1 || format >= 3;
    }
    if (strcmp(what, "rgb") == 0) {
        return format == 2 || format == 3 || format == 5 || format == 7 || format == 8 ||
               format == 10;
    }
    if (strcmp(what, "nir") == 0) {
        return format == 8 || format == 10;
    }
    return format == 4 || format == 5 || format == 9 || format == 10; // wave
}

// Walks the record field by field, as the specification's tables list them.
static void ref_decode(const uint8_t *r, int format, ref_point *o)
{
    memset(o, 0, sizeof(*o));
    o->X = get_signed(r, 4);
    o->Y = get_signed(r + 4, 4);
    o->Z = get_signed(r + 8, 4);
    o->intensity = (unsigned)get_le(r + 12, 2);
    size_t at;
    if (format <= 5) {
        o->return_number = r[14] % 8;
        o->number_of_returns = (r[14] / 8) % 8;
        o->scan_direction = (r[14] / 64) % 2;
        o->edge = r[14] / 128;
        o->classification = r[15] % 32;
        o->flags = r[15] / 32;
        o->scan_angle_raw = (int)get_signed(r + 16, 1);
        o->user_data = r[17];
        o->point_source_id = (unsigned)get_le(r + 18, 2);
        at = 20;
    } else {
        o->return_number = r[14] % 16;
        o->number_of_returns = r[14] / 16;
        o->flags = r[15] % 16;
        o->channel = (r[15] / 16) % 4;
        o->scan_direction = (r[15] / 64) % 2;
        o->edge = r[15] / 128;
        o->classification = r[16];
        o->user_data = r[17];
        o->scan_angle_raw = (int)get_signed(r + 18, 2);
        o->point_source_id = (unsigned)get_le(r + 20, 2);
        at = 22;
    }
    if (format_has(format, "gps")) {
        unsigned long long bits = get_le(r + at, 8);
        memcpy(&o->gps_time, &bits, 8);
        at += 8;
    }
    if (format_has(format, "rgb")) {
        o->red = (unsigned)get_le(r + at, 2);
        o->green = (unsigned)get_le(r + at + 2, 2);
        o->blue = (unsigned)get_le(r + at + 4, 2);
        at += 6;
    }
    if (format_has(format, "nir")) {
        o->nir = (unsigned)get_le(r + at, 2);
        at += 2;
    }
    if (format_has(format, "wave")) {
        o->wave_index = r[at];
        o->wave_offset = get_le(r + at + 1, 8);
        o->wave_size = (unsigned)get_le(r + at + 9, 4);
        float *floats[4] = { &o->wave_location, &o->wave_xt, &o->wave_yt, &o->wave_zt };
        for (int k = 0; k < 4; k++) {
            uint32_t bits = (uint32_t)get_le(r + at + 13 + 4 * k, 4);
            memcpy(floats[k], &bits, 4);
        }
        at += 29;
    }
    assert_int_equal(at, spec_sizes[format]);
}

// The inverse of ref_decode, for building records the corpus lacks.
static void ref_encode(const ref_point *o, int format, uint8_t *r)
{
    put_le(r, (unsigned long long)o->X, 4);
    put_le(r + 4, (unsigned long long)o->Y, 4);
    put_le(r + 8, (unsigned long long)o->Z, 4);
    put_le(r + 12, o->intensity, 2);
    size_t at;
    if (format <= 5) {
        r[14] = (uint8_t)(o->return_number | o->number_of_returns << 3 | o->scan_direction << 6 |
                          o->edge << 7);
        r[15] = (uint8_t)(o->classification | o->flags << 5);
        put_le(r + 16, (unsigned long long)o->scan_angle_raw, 1);
        r[17] = (uint8_t)o->user_data;
        put_le(r + 18, o->point_source_id, 2);
        at = 20;
    } else {
        r[14] = (uint8_t)(o->return_number | o->number_of_returns << 4);
        r[15] = (uint8_t)(o->flags | o->channel << 4 | o->scan_direction << 6 | o->edge << 7);
        r[16] = (uint8_t)o->classification;
        r[17] = (uint8_t)o->user_data;
        put_le(r + 18, (unsigned long long)o->scan_angle_raw, 2);
        put_le(r + 20, o->point_source_id, 2);
        at = 22;
    }
    if (format_has(format, "gps")) {
        unsigned long long bits;
        memcpy(&bits, &o->gps_time, 8);
        put_le(r + at, bits, 8);
        at += 8;
    }
    if (format_has(format, "rgb")) {
        put_le(r + at, o->red, 2);
        put_le(r + at + 2, o->green, 2);
        put_le(r + at + 4, o->blue, 2);
        at += 6;
    }
    if (format_has(format, "nir")) {
        put_le(r + at, o->nir, 2);
        at += 2;
    }
    if (format_has(format, "wave")) {
        r[at] = (uint8_t)o->wave_index;
        put_le(r + at + 1, o->wave_offset, 8);
        put_le(r + at + 9, o->wave_size, 4);
        const float floats[4] = { o->wave_location, o->wave_xt, o->wave_yt, o->wave_zt };
        for (int k = 0; k < 4; k++) {
            uint32_t bits;
            memcpy(&bits, &floats[k], 4);
            put_le(r + at + 13 + 4 * k, bits, 4);
        }
    }
}

static void assert_point_equals_ref(const sta_point *p, const ref_point *o, int format,
                                    const char *file, unsigned long long index)
{
    int expected_angle = format <= 5 ? (int)lround(o->scan_angle_raw / 0.006) : o->scan_angle_raw;
    bool same = p->X == o->X && p->Y == o->Y && p->Z == o->Z && p->intensity == o->intensity &&
                p->return_number == o->return_number &&
                p->number_of_returns == o->number_of_returns &&
                p->scan_direction_flag == o->scan_direction && p->edge_of_flight_line == o->edge &&
                p->classification == o->classification && p->classification_flags == o->flags &&
                p->scanner_channel == o->channel && p->user_data == o->user_data &&
                p->point_source_id == o->point_source_id && p->scan_angle == expected_angle &&
                memcmp(&p->gps_time, &o->gps_time, sizeof(double)) == 0 && p->red == o->red &&
                p->green == o->green && p->blue == o->blue && p->nir == o->nir &&
                p->wave_descriptor_index == o->wave_index &&
                p->wave_byte_offset == o->wave_offset && p->wave_packet_size == o->wave_size &&
                memcmp(&p->wave_return_location, &o->wave_location, sizeof(float)) == 0 &&
                memcmp(&p->wave_xt, &o->wave_xt, sizeof(float)) == 0 &&
                memcmp(&p->wave_yt, &o->wave_yt, sizeof(float)) == 0 &&
                memcmp(&p->wave_zt, &o->wave_zt, sizeof(float)) == 0;
    if (!same) {
        fail_msg("%s: point %llu differs from the independent decoding: X %d/%lld Y %d/%lld "
                 "Z %d/%lld intensity %u/%u return %u/%u of %u/%u class %u/%u flags %u/%u "
                 "angle %d/%d gps %.17g/%.17g rgb %u,%u,%u/%u,%u,%u nir %u/%u wave %u/%u "
                 "%llu/%llu",
                 file, index, p->X, o->X, p->Y, o->Y, p->Z, o->Z, p->intensity, o->intensity,
                 p->return_number, o->return_number, p->number_of_returns, o->number_of_returns,
                 p->classification, o->classification, p->classification_flags, o->flags,
                 p->scan_angle, expected_angle, p->gps_time, o->gps_time, p->red, p->green, p->blue,
                 o->red, o->green, o->blue, p->nir, o->nir, p->wave_descriptor_index, o->wave_index,
                 (unsigned long long)p->wave_byte_offset, o->wave_offset);
    }
}

// Reads all points of `data` and compares each (and its extra bytes) with ref_decode.
static void compare_with_ref(const uint8_t *data, size_t size, const char *name, size_t capacity,
                             unsigned long long expected_count)
{
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    if (sta_cloud_open_memory(data, size, name, NULL, &reader, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    assert_int_equal(info->point_count, expected_count);
    int format = info->point_format;
    size_t record_length = info->record_length;
    size_t extra = record_length - spec_sizes[format];
    assert_int_equal(info->extra_size, extra);
    const uint8_t *records = data + info->offset_to_point_data;
    sta_point_batch batch = { 0 };
    assert_int_equal(sta_point_batch_init(&batch, capacity, extra, &err), STA_OK);
    unsigned long long seen = 0;
    while (sta_cloud_read(reader, &batch, &err) == STA_OK && batch.count > 0) {
        for (size_t i = 0; i < batch.count; i++, seen++) {
            ref_point ref;
            ref_decode(records + seen * record_length, format, &ref);
            assert_point_equals_ref(&batch.points[i], &ref, format, name, seen);
            if (extra) {
                assert_memory_equal(batch.extra + i * extra,
                                    records + seen * record_length + spec_sizes[format], extra);
            }
        }
    }
    assert_int_equal(err.code, STA_OK);
    assert_int_equal(seen, expected_count);
    sta_point_batch_release(&batch);
    sta_cloud_close(reader);
}

static void point_fields_match_independent_decoder(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const char *const files[] = { "las/simple.las",           "las/1815.las",
                                         "las/test1_4.las",          "las/simple1_3.las",
                                         "las/gib_las_col.las",      "las/simple1_4.las",
                                         "las/5points_14.las",       "las/extra-bytes.las",
                                         "las/point10.las",          "las/point-color.las",
                                         "las/TO_core_last_clip.las" };
    for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); i++) {
        const las_fact *f = find_fact(files[i]);
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(files[i]), &size);
        compare_with_ref(data, size, files[i], 333, f->point_count);
        free(data);
    }
}

typedef struct anchor {
    const char *file;
    unsigned long long index;
    long long X, Y, Z;
    unsigned intensity, return_number, number_of_returns, classification, flags;
    int scan_angle;
    double gps_time;
    unsigned red, green, blue, nir;
} anchor;

/* First and last records as python3's struct module reads them (a one-off run). The
 * scan angle is the reader's unit: legacy degrees r give round(r / 0.006). */
static void first_and_last_points_match_python(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const anchor anchors[] = {
        { "las/simple.las", 0, 63701224, 84902831, 43166, 143, 1, 1, 1, 0, -1500,
          245380.78254962614, 68, 77, 88, 0 },
        { "las/simple.las", 1064, 63734285, 85324032, 42392, 116, 1, 1, 1, 0, 1500,
          249773.20172406783, 138, 107, 136, 0 },
        { "las/1815.las", 0, -84318400, -2215951, 2826796, 5727, 1, 1, 1, 0, 2500, 175050112.0, 0,
          0, 0, 0 },
        { "las/1815.las", 1246, 2120969, 97163528, 1904661, 34670, 1, 1, 2, 0, 2500, 175511184.0, 0,
          0, 0, 0 },
        { "las/test1_4.las", 0, 1726072618, -860129774, -1746345863, 41, 1, 1, 2, 8, 3005,
          83177420.53400505, 0, 0, 0, 0 },
        { "las/test1_4.las", 999, 1538225423, -864337581, -1747611844, 36, 1, 1, 2, 8, 2504,
          83177420.60104504, 0, 0, 0, 0 },
        { "las/simple1_3.las", 0, -234935841, 800843145, 265094, 1, 1, 1, 1, 0, -3000,
          129850.00006503289, 0, 0, 0, 0 },
        { "las/simple1_3.las", 998, -235433760, 800946080, 273729, 79, 1, 1, 1, 0, 3167,
          129850.00894958922, 0, 0, 0, 0 },
        { "las/gib_las_col.las", 0, 48499993, 648499975, 10273, 3035, 1, 1, 1, 0, -2000,
          316449286.7595554, 46848, 44288, 41984, 0 },
        { "las/gib_las_col.las", 6235, 48499669, 648419146, 9239, 3419, 1, 1, 1, 0, 667,
          316447645.5192485, 33536, 30976, 28672, 0 },
    };
    for (size_t i = 0; i < sizeof(anchors) / sizeof(anchors[0]); i++) {
        const anchor *a = &anchors[i];
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        assert_int_equal(sta_cloud_open(sta_test_shared_path(a->file), NULL, &reader, &err),
                         STA_OK);
        assert_int_equal(sta_cloud_seek(reader, a->index, &err), STA_OK);
        sta_point_batch batch = { 0 };
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(sta_point_batch_init(&batch, 2, info->extra_size, &err), STA_OK);
        assert_int_equal(sta_cloud_read(reader, &batch, &err), STA_OK);
        assert_true(batch.count >= 1); // the last point, or the first of two
        const sta_point *p = &batch.points[0];
        print_message("%s point %llu\n", a->file, a->index);
        assert_int_equal(p->X, (int32_t)a->X);
        assert_int_equal(p->Y, (int32_t)a->Y);
        assert_int_equal(p->Z, (int32_t)a->Z);
        assert_int_equal(p->intensity, a->intensity);
        assert_int_equal(p->return_number, a->return_number);
        assert_int_equal(p->number_of_returns, a->number_of_returns);
        assert_int_equal(p->classification, a->classification);
        assert_int_equal(p->classification_flags, a->flags);
        assert_int_equal(p->scan_angle, a->scan_angle);
        assert_true(p->gps_time == a->gps_time);
        assert_int_equal(p->red, a->red);
        assert_int_equal(p->green, a->green);
        assert_int_equal(p->blue, a->blue);
        assert_int_equal(p->nir, a->nir);
        if (strcmp(a->file, "las/simple1_3.las") == 0) {
            // python: wave packet (1, 316, 256, 22493.25390625, ...) and (1, 255804, 256,
            // 22828.205078125, ...).
            assert_int_equal(p->wave_descriptor_index, 1);
            assert_int_equal(p->wave_byte_offset, a->index == 0 ? 316 : 255804);
            assert_int_equal(p->wave_packet_size, 256);
            assert_true(p->wave_return_location ==
                        (a->index == 0 ? 22493.25390625f : 22828.205078125f));
        }
        sta_point_batch_release(&batch);
        sta_cloud_close(reader);
    }
}

/* ---- synthetic files ---------------------------------------------------------------- */

// Fields of synthetic point i in format `format`, spread over each field's range.
static void synthetic_point(int format, unsigned i, ref_point *o)
{
    memset(o, 0, sizeof(*o));
    o->X = 1000 + (long long)i * 7919;
    o->Y = -2000 - (long long)i * 104729;
    o->Z = i % 2 ? 2147483647LL - i : -2147483647LL - 1 + i;
    o->intensity = (i * 2311u) % 65536u;
    if (format <= 5) {
        o->return_number = i % 8;
        o->number_of_returns = 7 - i % 8;
        o->classification = (i * 3) % 32;
        o->flags = i % 8;
        o->scan_angle_raw = (int)(i % 256) - 128;
    } else {
        o->return_number = i % 16;
        o->number_of_returns = 15 - i % 16;
        o->classification = (i * 37) % 256;
        o->flags = i % 16;
        o->channel = (i / 3) % 4;
        o->scan_angle_raw = (int)((i * 1234u) % 65536u) - 32768;
    }
    o->scan_direction = i % 2;
    o->edge = (i / 2) % 2;
    o->user_data = (i * 11) % 256;
    o->point_source_id = (i * 401) % 65536;
    if (format_has(format, "gps")) {
        o->gps_time = 1e8 + i * 0.25;
    }
    if (format_has(format, "rgb")) {
        o->red = (i * 1000) % 65536;
        o->green = 2000 + i;
        o->blue = 65535 - i;
    }
    if (format_has(format, "nir")) {
        o->nir = 4242 + i;
    }
    if (format_has(format, "wave")) {
        o->wave_index = 1 + i % 255;
        o->wave_offset = 0x100000000ull + i * 4096ull;
        o->wave_size = 256 + i;
        o->wave_location = 12.5f + (float)i;
        o->wave_xt = 0.25f;
        o->wave_yt = -0.5f / (float)(i + 1);
        o->wave_zt = 1e-3f;
    }
}

/* A LAS 1.4 file of `count` synthetic points in `format` with `extra` undeclared bytes
 * per record, on the header of las/unregistered_extra_bytes.las (375 bytes, no VLRs,
 * points at 375). Returns a malloc'ed buffer. */
static uint8_t *build_synthetic(int format, size_t extra, unsigned count, size_t *out_size)
{
    size_t base_size = 0;
    uint8_t *base =
        sta_test_read_file(sta_test_shared_path("las/unregistered_extra_bytes.las"), &base_size);
    assert_true(base_size >= 375);
    size_t record_length = spec_sizes[format] + extra;
    size_t size = 375 + (size_t)count * record_length;
    uint8_t *data = calloc(1, size);
    assert_non_null(data);
    memcpy(data, base, 375);
    free(base);
    data[104] = (uint8_t)format;
    put_le(data + 105, record_length, 2);
    put_le(data + 107, 0, 4); // legacy count 0, as 1.4 wants for formats 6-10
    put_le(data + 227, 0, 8); // no waveform data
    put_le(data + 235, 0, 8); // no EVLRs
    put_le(data + 243, 0, 4);
    put_le(data + 247, count, 8); // 64-bit point count
    for (unsigned i = 0; i < count; i++) {
        ref_point p;
        synthetic_point(format, i, &p);
        uint8_t *r = data + 375 + (size_t)i * record_length;
        ref_encode(&p, format, r);
        for (size_t k = 0; k < extra; k++) {
            r[spec_sizes[format] + k] = (uint8_t)(i * 31 + k);
        }
    }
    *out_size = size;
    return data;
}

static void synthetic_formats_5_9_10_decode(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const int formats[] = { 5, 9, 10 };
    for (size_t k = 0; k < 3; k++) {
        int format = formats[k];
        size_t size = 0;
        uint8_t *data = build_synthetic(format, 2, 300, &size);
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        if (sta_cloud_open_memory(data, size, "synthetic.las", NULL, &reader, &err) != STA_OK) {
            fail_msg("format %d: %s", format, err.message);
        }
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(info->point_format, format);
        assert_int_equal(info->record_length, spec_sizes[format] + 2);
        assert_true(info->has_waveform_packets);
        assert_int_equal(info->attributes, expected_attributes(format));
        assert_true(info->attributes & STA_ATTR_WAVE_PACKET);
        assert_int_equal((info->attributes & STA_ATTR_RGB) != 0, format != 9); // 9 = 6 + wave
        assert_int_equal((info->attributes & STA_ATTR_NIR) != 0, format == 10);
        assert_int_equal(info->extra_dim_count, 1);
        assert_string_equal(info->extra_dims[0].name, "undeclared");
        assert_int_equal(info->extra_dims[0].size_bytes, 2);

        // Spot-check point 7 by hand, then all points against the reference.
        sta_point_batch batch = { 0 };
        assert_int_equal(sta_point_batch_init(&batch, 64, 2, &err), STA_OK);
        assert_int_equal(sta_cloud_read(reader, &batch, &err), STA_OK);
        const sta_point *p = &batch.points[7];
        assert_int_equal(p->wave_descriptor_index, 8);
        assert_int_equal(p->wave_byte_offset, 0x100000000ull + 7 * 4096);
        assert_int_equal(p->wave_packet_size, 263);
        assert_true(p->wave_return_location == 19.5f);
        assert_true(p->wave_xt == 0.25f && p->wave_yt == -0.5f / 8.0f && p->wave_zt == 1e-3f);
        assert_int_equal(p->red, format == 9 ? 0 : 7000);
        assert_int_equal(p->green, format == 9 ? 0 : 2007);
        assert_int_equal(p->blue, format == 9 ? 0 : 65528);
        assert_int_equal(p->nir, format == 10 ? 4249 : 0);
        assert_true(p->gps_time == 1e8 + 1.75);
        assert_int_equal(batch.extra[7 * 2], (uint8_t)(7 * 31));
        assert_int_equal(batch.extra[7 * 2 + 1], (uint8_t)(7 * 31 + 1));
        sta_point_batch_release(&batch);
        sta_cloud_close(reader);
        compare_with_ref(data, size, "synthetic.las", 64, 300);
        free(data);
    }
}

// Formats 0-10 all decode like the reference, with and without trailing bytes.
static void synthetic_every_format_decodes(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    for (int format = 0; format <= 10; format++) {
        for (size_t extra = 0; extra <= 5; extra += 5) {
            size_t size = 0;
            uint8_t *data = build_synthetic(format, extra, 517, &size);
            compare_with_ref(data, size, "synthetic.las", 100, 517);
            free(data);
        }
    }
}

// Legacy scan angle ranks become 0.006-degree units; class bits 5-7 become flags.
static void legacy_scan_angle_and_class_flags(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("las/liblas_1.2_0.las"), &size);
    assert_int_equal(size, 458); // README: offset to point data 438, PDRF 0, one point
    static const struct {
        int8_t rank;
        int16_t angle;
    } angles[] = { { -90, -15000 }, { 90, 15000 },  { 1, 167 },       { -1, -167 },
                   { 0, 0 },        { 127, 21167 }, { -128, -21333 }, { 4, 667 } };
    for (size_t i = 0; i < sizeof(angles) / sizeof(angles[0]); i++) {
        data[438 + 16] = (uint8_t)angles[i].rank;
        data[438 + 15] = (uint8_t)(0xa0 | 9); // withheld + synthetic, class 9
        data[438 + 14] = (uint8_t)(3 | 5 << 3 | 1 << 6 | 1 << 7);
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        assert_int_equal(sta_cloud_open_memory(data, size, "angle.las", NULL, &reader, &err),
                         STA_OK);
        sta_point_batch batch = { 0 };
        assert_int_equal(sta_point_batch_init(&batch, 1, 0, &err), STA_OK);
        assert_int_equal(sta_cloud_read(reader, &batch, &err), STA_OK);
        assert_int_equal(batch.count, 1);
        assert_int_equal(batch.points[0].scan_angle, angles[i].angle);
        assert_int_equal(batch.points[0].scan_angle, lround(angles[i].rank / 0.006));
        assert_int_equal(batch.points[0].classification, 9);
        assert_int_equal(batch.points[0].classification_flags, 5); // bits 0 and 2
        assert_int_equal(batch.points[0].return_number, 3);
        assert_int_equal(batch.points[0].number_of_returns, 5);
        assert_int_equal(batch.points[0].scan_direction_flag, 1);
        assert_int_equal(batch.points[0].edge_of_flight_line, 1);
        assert_int_equal(batch.points[0].scanner_channel, 0);
        sta_point_batch_release(&batch);
        sta_cloud_close(reader);
    }
    free(data);
}

static void record_sizes_follow_the_spec(void **state)
{
    (void)state;
    for (int format = 0; format <= 10; format++) {
        assert_int_equal(sta_las_format_record_size(format), spec_sizes[format]);
    }
    assert_int_equal(sta_las_format_record_size(11), 0);
    assert_int_equal(sta_las_format_record_size(-1), 0);
    assert_int_equal(sta_las_format_record_size(128 + 3), 0);
}

/* ---- headers that lie ------------------------------------------------------------ */

typedef struct mutation {
    const char *base; /* shared file to start from */
    size_t at;        /* byte offset of the field */
    int width;        /* 1, 2, 4 or 8 bytes (integer), or -8 for a double */
    unsigned long long value;
    double real;         /* for width -8 */
    long long past_size; /* when non-zero: value = file size + past_size */
    sta_status code;
    const char *needle;  /* must appear in the message (the field and its value) */
    const char *needle2; /* may be NULL */
} mutation;

static void expect_open_failure(const uint8_t *data, size_t size, const sta_read_options *options,
                                sta_status code, const char *needle, const char *needle2)
{
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    sta_status status = sta_cloud_open_memory(data, size, "mutant.las", options, &reader, &err);
    if (status != code) {
        fail_msg("expected %s for \"%s\", got %s: %s", sta_status_str(code), needle,
                 sta_status_str(status), err.message);
    }
    assert_null(reader);
    if (!contains(err.message, "mutant.las") || !contains(err.message, needle) ||
        (needle2 && !contains(err.message, needle2))) {
        fail_msg("message \"%s\" lacks \"%s\" / \"%s\"", err.message, needle,
                 needle2 ? needle2 : "");
    }
}

static void lying_headers_are_named(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    // simple.las: LAS 1.2, 36437 bytes, 1065 x 34-byte records from 227, no VLRs.
    // 1_4_w_evlr.las: LAS 1.4, 32381 bytes, 1000 x 30-byte records from 2305, VLR 0 at
    // 375, one EVLR at 32305. simple1_3.las: waveform record at 62728, file 62888 bytes.
    static const mutation mutations[] = {
        { "las/simple.las", 131, -8, 0, 0.0, 0, STA_ERR_FORMAT, "x scale factor 0", NULL },
        { "las/simple.las", 139, -8, 0, (double)NAN, 0, STA_ERR_FORMAT, "y scale factor", "nan" },
        { "las/simple.las", 147, -8, 0, -0.01, 0, STA_ERR_FORMAT, "z scale factor -0.01", NULL },
        { "las/simple.las", 131, -8, 0, HUGE_VAL, 0, STA_ERR_FORMAT, "x scale factor inf", NULL },
        { "las/simple.las", 163, -8, 0, (double)NAN, 0, STA_ERR_FORMAT, "y offset nan", NULL },
        { "las/simple.las", 171, -8, 0, -HUGE_VAL, 0, STA_ERR_FORMAT, "z offset -inf", NULL },
        { "las/simple.las", 107, 4, 1066, 0, 0, STA_ERR_FORMAT, "point count 1066",
          "1065 complete records" },
        { "las/simple.las", 107, 4, 0xffffffffu, 0, 0, STA_ERR_FORMAT, "point count 4294967295",
          NULL },
        { "las/simple.las", 96, 4, 0, 0, 1, STA_ERR_FORMAT, "offset_to_point_data 36438",
          "past the end" },
        { "las/simple.las", 96, 4, 200, 0, 0, STA_ERR_FORMAT, "offset_to_point_data 200",
          "inside" },
        { "las/simple.las", 105, 2, 33, 0, 0, STA_ERR_FORMAT, "record length 33",
          "point format 3" },
        { "las/simple.las", 104, 1, 11, 0, 0, STA_ERR_FORMAT, "point data format 11", NULL },
        { "las/simple.las", 104, 1, 63, 0, 0, STA_ERR_FORMAT, "point data format 63", NULL },
        { "las/simple.las", 104, 1, 0x83, 0, 0, STA_ERR_UNSUPPORTED, "LAZ", "0x83" },
        { "las/simple.las", 104, 1, 0x43, 0, 0, STA_ERR_UNSUPPORTED, "LAZ", "0x43" },
        { "las/simple.las", 94, 2, 226, 0, 0, STA_ERR_FORMAT, "header_size 226", NULL },
        { "las/simple.las", 94, 2, 60000, 0, 0, STA_ERR_FORMAT, "header_size 60000", NULL },
        { "las/simple.las", 25, 1, 3, 0, 0, STA_ERR_FORMAT, "header_size 227", "1.3" },
        { "las/simple.las", 25, 1, 5, 0, 0, STA_ERR_UNSUPPORTED, "version 1.5", NULL },
        { "las/simple.las", 24, 1, 2, 0, 0, STA_ERR_UNSUPPORTED, "version 2.2", NULL },
        { "las/simple.las", 100, 4, 1, 0, 0, STA_ERR_FORMAT, "number of VLRs 1", NULL },
        { "las/1_4_w_evlr.las", 235, 8, 0, 0, 100, STA_ERR_FORMAT, "start_of_first_evlr 32481",
          "past the end" },
        { "las/1_4_w_evlr.las", 235, 8, 100, 0, 0, STA_ERR_FORMAT, "start_of_first_evlr 100",
          "inside" },
        { "las/1_4_w_evlr.las", 235, 8, 0, 0, 0, STA_ERR_FORMAT, "start_of_first_evlr 0", NULL },
        { "las/1_4_w_evlr.las", 243, 4, 0xffffffffu, 0, 0, STA_ERR_FORMAT,
          "4294967295 EVLRs (number of EVLRs)", NULL },
        { "las/1_4_w_evlr.las", 243, 4, 2, 0, 0, STA_ERR_FORMAT, "2 EVLRs (number of EVLRs)",
          "start_of_first_evlr 32305" },
        { "las/1_4_w_evlr.las", 247, 8, 1001, 0, 0, STA_ERR_FORMAT, "start_of_first_evlr 32305",
          "point count 1001" },
        { "las/1_4_w_evlr.las", 247, 8, 1003, 0, 0, STA_ERR_FORMAT, "point count 1003",
          "1002 complete records" },
        { "las/1_4_w_evlr.las", 247, 8, 1ull << 62, 0, 0, STA_ERR_FORMAT,
          "point count 4611686018427387904", "more than 2^64" },
        { "las/1_4_w_evlr.las", 32305 + 20, 8, 1000, 0, 0, STA_ERR_FORMAT, "EVLR 0",
          "past the end" },
        { "las/1_4_w_evlr.las", 375 + 20, 2, 60000, 0, 0, STA_ERR_FORMAT, "VLR 0",
          "offset_to_point_data 2305" },
        { "las/1_4_w_evlr.las", 94, 2, 374, 0, 0, STA_ERR_FORMAT, "header_size 374", "1.4" },
        { "las/1_4_w_evlr.las", 100, 4, 43, 0, 0, STA_ERR_FORMAT, "number of VLRs 43", NULL },
        { "las/1_4_w_evlr.las", 100, 4, 3, 0, 0, STA_ERR_FORMAT, "VLR 2 of 3 (number of VLRs)",
          "offset_to_point_data 2305" },
    };
    for (size_t i = 0; i < sizeof(mutations) / sizeof(mutations[0]); i++) {
        const mutation *m = &mutations[i];
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(m->base), &size);
        unsigned long long value =
            m->past_size ? size + (unsigned long long)m->past_size : m->value;
        if (m->width == -8) {
            unsigned long long bits;
            memcpy(&bits, &m->real, 8);
            put_le(data + m->at, bits, 8);
        } else {
            put_le(data + m->at, value, m->width);
        }
        print_message("mutation %zu: %s\n", i, m->needle);
        expect_open_failure(data, size, NULL, m->code, m->needle, m->needle2);
        free(data);
    }
}

// Runs sta_cloud_open_memory with stderr sent to a file; returns what was written
// (static buffer) and the reader in *out_reader.
static const char *open_capturing_warnings(const uint8_t *data, size_t size,
                                           const sta_read_options *options,
                                           sta_cloud_reader **out_reader, sta_error *err)
{
    static char text[4096];
    fflush(stderr);
    FILE *capture = tmpfile();
    assert_non_null(capture);
    int saved = dup(2);
    assert_true(saved >= 0);
    assert_true(dup2(fileno(capture), 2) >= 0);
    sta_status status = sta_cloud_open_memory(data, size, "mutant.las", options, out_reader, err);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    rewind(capture);
    size_t n = fread(text, 1, sizeof(text) - 1, capture);
    text[n] = '\0';
    fclose(capture);
    if (status != STA_OK) {
        fail_msg("open failed: %s", err->message);
    }
    return text;
}

/* Decision (see src/io/las_vlr.c): a LAS 1.3 start_of_waveform_data that cannot hold
 * the waveform record (past the end, or inside the points) warns and the points are
 * read, as the same defect in 1.4 does. simple1_3.las: 999 points from 5785, waveform
 * record at 62728, file 62888 bytes. */
static void dangling_waveform_pointer_warns_in_1_3_and_1_4(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const struct {
        const char *file;
        unsigned long long start; /* 0: file size + 8 */
        unsigned long long points;
        const char *needle;
    } cases[] = {
        { "las/simple1_3.las", 0, 999, "start_of_waveform_data 62896" },
        { "las/simple1_3.las", 62880, 999, "start_of_waveform_data 62880" },
        { "las/simple1_3.las", 5000, 999, "start_of_waveform_data 5000" },
        { "las/1_4_w_evlr.las", 0, 1000, "start_of_waveform_data 32389" },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(cases[i].file), &size);
        put_le(data + 227, cases[i].start ? cases[i].start : size + 8, 8);
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        const char *warnings = open_capturing_warnings(data, size, NULL, &reader, &err);
        if (!contains(warnings, cases[i].needle) || !contains(warnings, "mutant.las")) {
            fail_msg("case %zu: warning \"%s\" lacks \"%s\"", i, warnings, cases[i].needle);
        }
        assert_false(contains(warnings, "EVLRs"));
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(info->point_count, cases[i].points);
        scan_result scan;
        scan_points(reader, 256, &scan);
        assert_int_equal(scan.count, cases[i].points);
        sta_cloud_close(reader);
        free(data);
    }
}

/* A VLR count that overshoots: an error by default; salvage keeps the whole VLRs
 * before the bad one and reads every point. 1_4_w_evlr.las: two VLRs from 375, one
 * EVLR, 1000 points from 2305. */
static void overshooting_vlr_count_is_salvaged(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const unsigned long long counts[] = { 3, 43, 0xffffffffull };
    for (size_t i = 0; i < sizeof(counts) / sizeof(counts[0]); i++) {
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path("las/1_4_w_evlr.las"), &size);
        put_le(data + 100, counts[i], 4);
        expect_open_failure(data, size, NULL, STA_ERR_FORMAT, "VLR", "offset_to_point_data 2305");
        sta_read_options options = { .salvage_truncated = true };
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        const char *warnings = open_capturing_warnings(data, size, &options, &reader, &err);
        assert_true(contains(warnings, "keeping the 2 whole VLRs"));
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(info->vlr_count, 3); // the VLRs and the EVLR
        assert_int_equal(info->point_count, 1000);
        scan_result scan;
        scan_points(reader, 256, &scan);
        assert_int_equal(scan.count, 1000);
        sta_cloud_close(reader);
        free(data);
    }
}

/* Text from the file reaches messages escaped: a user id with an escape character
 * and bytes that are not UTF-8 shows as \xNN, never raw. */
static void messages_escape_file_text(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("las/1_4_w_evlr.las"), &size);
    memcpy(data + 375 + 2, "ab\x1b[31m\xff\xfe\\z", 11);
    put_le(data + 375 + 20, 60000, 2); // the VLR runs past the points: an error naming it
    expect_open_failure(data, size, NULL, STA_ERR_FORMAT, "ab\\x1b[31m\\xff\\xfe\\x5cz",
                        "offset_to_point_data 2305");
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    sta_cloud_open_memory(data, size, "mutant.las", NULL, &reader, &err);
    for (const char *c = err.message; *c; c++) {
        assert_true((unsigned char)*c >= 0x20 && (unsigned char)*c < 0x7f);
    }
    free(data);
}

static void laszip_vlr_is_refused(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("las/1_4_w_evlr.las"), &size);
    // Turn VLR 0 (at 375) into a LASzip VLR without touching the format byte.
    memset(data + 375 + 2, 0, 16);
    memcpy(data + 375 + 2, "laszip encoded", 14);
    put_le(data + 375 + 18, 22204, 2);
    expect_open_failure(data, size, NULL, STA_ERR_UNSUPPORTED, "LAZ", "laszip encoded");
    free(data);
}

/* Decision (see src/io/las_header.c): in LAS 1.4 the 64-bit count wins; a non-zero
 * legacy count that disagrees only warns. */
static void legacy_count_disagreement_uses_64_bit_count(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("las/1_4_w_evlr.las"), &size);
    put_le(data + 107, 999, 4);
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_cloud_open_memory(data, size, "legacy.las", NULL, &reader, &err), STA_OK);
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    assert_int_equal(info->legacy_point_count, 999);
    assert_int_equal(info->header_point_count, 1000);
    assert_int_equal(info->point_count, 1000);
    scan_result scan;
    scan_points(reader, 1000, &scan);
    assert_int_equal(scan.count, 1000);
    sta_cloud_close(reader);
    free(data);
}

/* Prefixes of valid files (tests/fuzz replays every one of its corpus): by default an error unless
 * complete; with salvage, either an error (cut in the header or VLRs) or exactly the complete
 * records and the EVLRs that are whole. Each prefix is fed as an exact-size heap copy so ASan sees
 * any read past its end. */
static void truncations_are_errors_or_consistent(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const char *const files[] = { "las/5points_14.las", "las/1_4_w_evlr.las",
                                         "las/liblas_1.0_1.las", "las/extra_byte.las" };
    sta_log_set_level(STA_LOG_QUIET); // salvaging warns at every cut
    for (size_t k = 0; k < sizeof(files) / sizeof(files[0]); k++) {
        const las_fact *f = find_fact(files[k]);
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(files[k]), &size);
        unsigned long long point_end =
            f->offset_to_point_data + f->point_count * (unsigned long long)f->record_length;
        // Every cut through the header, VLRs and EVLRs and the first and last records;
        // in between every 7th (coprime with the record lengths 28, 30 and 32).
        size_t head = f->offset_to_point_data + 2 * f->record_length;
        size_t tail = point_end > 2 * f->record_length ? point_end - 2 * f->record_length : 0;
        for (size_t length = 0; length <= size;
             length += (length >= head && length < tail) ? 7 : 1) {
            uint8_t *copy = malloc(length ? length : 1);
            assert_non_null(copy);
            memcpy(copy, data, length);
            for (int salvage = 0; salvage <= 1; salvage++) {
                sta_read_options options = { .salvage_truncated = salvage != 0 };
                sta_cloud_reader *reader = NULL;
                sta_error err = { 0 };
                sta_status status =
                    sta_cloud_open_memory(copy, length, "cut.las", &options, &reader, &err);
                bool should_open = length == size || (salvage && length >= f->offset_to_point_data);
                if (!should_open) {
                    if (status == STA_OK) {
                        fail_msg("%s cut to %zu bytes opened (salvage %d)", files[k], length,
                                 salvage);
                    }
                    assert_true(length < 4
                                    ? status == STA_ERR_UNSUPPORTED || status == STA_ERR_FORMAT
                                    : status == STA_ERR_FORMAT);
                    assert_true(contains(err.message, "cut.las"));
                    continue;
                }
                if (status != STA_OK) {
                    fail_msg("%s cut to %zu bytes (salvage %d): %s", files[k], length, salvage,
                             err.message);
                }
                const sta_cloud_info *info = sta_cloud_reader_info(reader);
                unsigned long long complete = (length - f->offset_to_point_data) / f->record_length;
                unsigned long long expected = length >= point_end ? f->point_count : complete;
                assert_int_equal(info->point_count, expected);
                assert_int_equal(info->skipped_point_count, f->point_count - expected);
                assert_int_equal(info->vlr_count,
                                 f->vlr_count + (length == size ? f->evlr_count : 0));
                scan_result scan;
                scan_points(reader, 16, &scan);
                assert_int_equal(scan.count, expected);
                sta_cloud_close(reader);
            }
            free(copy);
        }
        free(data);
    }
}

// Each allocation in open and read may fail: the result is then STA_ERR_NOMEM and
// nothing leaks (LeakSanitizer checks at exit).
static void allocation_failures_clean_up(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char path[4096];
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/simple1_4.las"));
    bool succeeded = false;
    long failures = 0;
    for (long n = 0; n < 64 && !succeeded; n++) {
        sta_alloc_fail_after(n);
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        sta_status status = sta_cloud_open(path, NULL, &reader, &err);
        unsigned long long read = 0;
        if (status == STA_OK) {
            const sta_cloud_info *info = sta_cloud_reader_info(reader);
            assert_non_null(info->crs_wkt); // the WKT EVLR was copied
            sta_point_batch batch = { 0 };
            status = sta_point_batch_init(&batch, 5000, info->extra_size, &err);
            while (status == STA_OK) {
                status = sta_cloud_read(reader, &batch, &err);
                if (status != STA_OK || batch.count == 0) {
                    break;
                }
                read += batch.count;
            }
            sta_point_batch_release(&batch);
            sta_cloud_close(reader);
        }
        sta_alloc_fail_after(-1);
        if (status == STA_OK) {
            assert_int_equal(read, 22600);
            succeeded = true;
        } else {
            if (status != STA_ERR_NOMEM) {
                fail_msg("allocation %ld failing gave %s: %s", n, sta_status_str(status),
                         err.message);
            }
            assert_true(contains(err.message, "memory"));
            failures++;
        }
    }
    assert_true(succeeded);
    assert_true(failures >= 4); // reader, path, LAS reader, VLRs, EVLRs, WKT, batch
}

/* ---- registration ------------------------------------------------------------------ */
static const struct CMUnitTest tests[] = {
    cmocka_unit_test(file_liblas_1_0_0),
    cmocka_unit_test(file_liblas_1_0_1),
    cmocka_unit_test(file_TO_core_last_clip),
    cmocka_unit_test(file_point10_1_0),
    cmocka_unit_test(file_Example),
    cmocka_unit_test(file_liblas_1_1_0),
    cmocka_unit_test(file_liblas_1_1_1),
    cmocka_unit_test(file_simple1_1),
    cmocka_unit_test(file_lots_of_vlr),
    cmocka_unit_test(file_liblas_1_2_0),
    cmocka_unit_test(file_liblas_1_2_1),
    cmocka_unit_test(file_liblas_1_2_2),
    cmocka_unit_test(file_liblas_1_2_3),
    cmocka_unit_test(file_point10),
    cmocka_unit_test(file_point_time),
    cmocka_unit_test(file_point_color),
    cmocka_unit_test(file_point_time_color),
    cmocka_unit_test(file_extra_bytes),
    cmocka_unit_test(file_simple),
    cmocka_unit_test(file_autzen_trim),
    cmocka_unit_test(file_autzen_point_format_3),
    cmocka_unit_test(file_1815),
    cmocka_unit_test(file_Megaplot),
    cmocka_unit_test(file_MixedConifer),
    cmocka_unit_test(file_extra_byte),
    cmocka_unit_test(file_gps_time_nan),
    cmocka_unit_test(file_long_header),
    cmocka_unit_test(file_epsg_4326),
    cmocka_unit_test(file_warsaw_small),
    cmocka_unit_test(file_1_2_empty_geotiff_vlrs),
    cmocka_unit_test(file_no_points),
    cmocka_unit_test(file_mvk_thin),
    cmocka_unit_test(file_sample_c),
    cmocka_unit_test(file_test_data_0000_0000_LA93_IGN69_ground),
    cmocka_unit_test(file_malformed_extrabytes),
    cmocka_unit_test(file_vegetation_1_3),
    cmocka_unit_test(file_simple1_3),
    cmocka_unit_test(file_no_points_1_3),
    cmocka_unit_test(file_test1_4),
    cmocka_unit_test(file_1_4_w_evlr),
    cmocka_unit_test(file_simple1_4),
    cmocka_unit_test(file_unregistered_extra_bytes),
    cmocka_unit_test(file_5points_14),
    cmocka_unit_test(file_autzen_bmx_2010),
    cmocka_unit_test(file_gib_las_col),
    cmocka_unit_test(clipped_file_is_an_error_by_default),
    cmocka_unit_test(clipped_file_salvages_1064_points),
    cmocka_unit_test(garbage_vlr_count_is_salvaged),
    cmocka_unit_test(malformed_extra_bytes_descriptor_is_ignored),
    cmocka_unit_test(laz_point14_reads_like_its_twin),
    cmocka_unit_test(corpus_table_covers_every_file),
    cmocka_unit_test(lion_200_files_sum_to_341989),
    cmocka_unit_test(point_fields_match_independent_decoder),
    cmocka_unit_test(first_and_last_points_match_python),
    cmocka_unit_test(synthetic_formats_5_9_10_decode),
    cmocka_unit_test(synthetic_every_format_decodes),
    cmocka_unit_test(legacy_scan_angle_and_class_flags),
    cmocka_unit_test(record_sizes_follow_the_spec),
    cmocka_unit_test(lying_headers_are_named),
    cmocka_unit_test(dangling_waveform_pointer_warns_in_1_3_and_1_4),
    cmocka_unit_test(overshooting_vlr_count_is_salvaged),
    cmocka_unit_test(messages_escape_file_text),
    cmocka_unit_test(laszip_vlr_is_refused),
    cmocka_unit_test(legacy_count_disagreement_uses_64_bit_count),
    cmocka_unit_test(truncations_are_errors_or_consistent),
    cmocka_unit_test(allocation_failures_clean_up),
};

STA_TEST_MAIN(tests)
