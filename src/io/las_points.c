/* SPDX-License-Identifier: MIT
 * LAS point data records, formats 0-10 (LAS 1.4 R15, tables 7-17): sizes, which
 * attributes each carries, and one decoder per format.
 *
 * Each decoder is the same inlined field-by-field decode instantiated with a constant
 * format, so the per-point loop has no format branches and no allocation. Formats
 * 0-5 store the scan angle rank in whole degrees; it becomes the 1.4 unit of 0.006
 * degree (round(deg / 0.006)). Their classification byte holds the class in bits
 * 0-4 and the synthetic, key-point and withheld flags in bits 5-7, which become
 * classification_flags bits 0-2.
 */
#include "core/bytes.h"
#include "io/las_internal.h"

static const uint8_t record_sizes[STA_LAS_MAX_POINT_FORMAT + 1] = { 20, 28, 26, 34, 57, 63,
                                                                    30, 36, 38, 59, 67 };

unsigned sta_las_format_record_size(int point_format)
{
    if (point_format < 0 || point_format > STA_LAS_MAX_POINT_FORMAT) {
        return 0;
    }
    return record_sizes[point_format];
}

static inline bool format_has_gps(int f)
{
    return f == 1 || f >= 3;
}

static inline bool format_has_rgb(int f)
{
    return f == 2 || f == 3 || f == 5 || f == 7 || f == 8 || f == 10;
}

static inline bool format_has_nir(int f)
{
    return f == 8 || f == 10;
}

static inline bool format_has_wave(int f)
{
    return f == 4 || f == 5 || f == 9 || f == 10;
}

uint32_t sta_las_format_attributes(int point_format)
{
    int f = point_format;
    uint32_t bits = STA_ATTR_INTENSITY | STA_ATTR_RETURNS | STA_ATTR_CLASSIFICATION |
                    STA_ATTR_SCAN_ANGLE | STA_ATTR_USER_DATA | STA_ATTR_POINT_SOURCE_ID |
                    STA_ATTR_SCAN_FLAGS;
    if (format_has_gps(f)) {
        bits |= STA_ATTR_GPS_TIME;
    }
    if (format_has_rgb(f)) {
        bits |= STA_ATTR_RGB;
    }
    if (format_has_nir(f)) {
        bits |= STA_ATTR_NIR;
    }
    if (format_has_wave(f)) {
        bits |= STA_ATTR_WAVE_PACKET;
    }
    if (f >= 6) {
        bits |= STA_ATTR_SCANNER_CHANNEL;
    }
    return bits;
}

// round(degrees / 0.006) in integers: degrees * 500 / 3 is never halfway between two
// integers, so adding one towards the sign and truncating rounds to nearest.
static inline int16_t legacy_scan_angle(int8_t degrees)
{
    int n = degrees * 500;
    return (int16_t)((n + (n >= 0 ? 1 : -1)) / 3);
}

// Byte offsets of the optional parts within a record of format f.
static inline unsigned rgb_at(int f)
{
    switch (f) {
    case 2:
        return 20;
    case 3:
    case 5:
        return 28;
    default: // 7, 8, 10
        return 30;
    }
}

static inline unsigned wave_at(int f)
{
    switch (f) {
    case 4:
        return 28;
    case 5:
        return 34;
    case 9:
        return 30;
    default: // 10
        return 38;
    }
}

static inline __attribute__((always_inline)) void decode_point(const uint8_t *p, int f,
                                                               sta_point *out)
{
    sta_point pt = { 0 };
    pt.X = sta_load_i32le(p);
    pt.Y = sta_load_i32le(p + 4);
    pt.Z = sta_load_i32le(p + 8);
    pt.intensity = sta_load_u16le(p + 12);
    if (f < 6) {
        uint8_t bits = p[14];
        pt.return_number = bits & 7u;
        pt.number_of_returns = (bits >> 3) & 7u;
        pt.scan_direction_flag = (bits >> 6) & 1u;
        pt.edge_of_flight_line = (uint8_t)(bits >> 7);
        uint8_t classification = p[15];
        pt.classification = classification & 31u;
        pt.classification_flags = (uint8_t)(classification >> 5);
        pt.scan_angle = legacy_scan_angle((int8_t)p[16]);
        pt.user_data = p[17];
        pt.point_source_id = sta_load_u16le(p + 18);
        if (format_has_gps(f)) {
            pt.gps_time = sta_load_f64le(p + 20);
        }
    } else {
        uint8_t returns = p[14];
        pt.return_number = returns & 15u;
        pt.number_of_returns = (uint8_t)(returns >> 4);
        uint8_t flags = p[15];
        pt.classification_flags = flags & 15u;
        pt.scanner_channel = (flags >> 4) & 3u;
        pt.scan_direction_flag = (flags >> 6) & 1u;
        pt.edge_of_flight_line = (uint8_t)(flags >> 7);
        pt.classification = p[16];
        pt.user_data = p[17];
        pt.scan_angle = sta_load_i16le(p + 18);
        pt.point_source_id = sta_load_u16le(p + 20);
        pt.gps_time = sta_load_f64le(p + 22);
    }
    if (format_has_rgb(f)) {
        const uint8_t *c = p + rgb_at(f);
        pt.red = sta_load_u16le(c);
        pt.green = sta_load_u16le(c + 2);
        pt.blue = sta_load_u16le(c + 4);
        if (format_has_nir(f)) {
            pt.nir = sta_load_u16le(c + 6);
        }
    }
    if (format_has_wave(f)) {
        const uint8_t *w = p + wave_at(f);
        pt.wave_descriptor_index = w[0];
        pt.wave_byte_offset = sta_load_u64le(w + 1);
        pt.wave_packet_size = sta_load_u32le(w + 9);
        pt.wave_return_location = sta_load_f32le(w + 13);
        pt.wave_xt = sta_load_f32le(w + 17);
        pt.wave_yt = sta_load_f32le(w + 21);
        pt.wave_zt = sta_load_f32le(w + 25);
    }
    *out = pt;
}

#define STA_LAS_DEFINE_DECODER(f)                                                                  \
 static void decode_format_##f(const uint8_t *src, size_t stride, sta_point *dst, size_t count)    \
 {                                                                                                 \
  for (size_t i = 0; i < count; i++) {                                                             \
   decode_point(src + i * stride, f, &dst[i]);                                                     \
  }                                                                                                \
 }

STA_LAS_DEFINE_DECODER(0)
STA_LAS_DEFINE_DECODER(1)
STA_LAS_DEFINE_DECODER(2)
STA_LAS_DEFINE_DECODER(3)
STA_LAS_DEFINE_DECODER(4)
STA_LAS_DEFINE_DECODER(5)
STA_LAS_DEFINE_DECODER(6)
STA_LAS_DEFINE_DECODER(7)
STA_LAS_DEFINE_DECODER(8)
STA_LAS_DEFINE_DECODER(9)
STA_LAS_DEFINE_DECODER(10)

sta_las_decode_fn sta_las_decoder(int point_format)
{
    static const sta_las_decode_fn decoders[STA_LAS_MAX_POINT_FORMAT + 1] = {
        decode_format_0, decode_format_1, decode_format_2,  decode_format_3,
        decode_format_4, decode_format_5, decode_format_6,  decode_format_7,
        decode_format_8, decode_format_9, decode_format_10,
    };
    if (point_format < 0 || point_format > STA_LAS_MAX_POINT_FORMAT) {
        return NULL;
    }
    return decoders[point_format];
}
