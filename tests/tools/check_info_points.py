#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Checks `strata-info --points` and `--json` against an independent LAS decoder.

The decoder below is written from the LAS 1.4 specification with Python's struct
module and shares no code with the C reader. For each LAS file it compares every
printed point (coordinates to 1e-9 relative, the other fields exactly) and a few
JSON facts. Exit 0: all match; 1: a mismatch; 77: shared data absent (skip).
"""
import json
import math
import os
import struct
import subprocess
import sys

FILES = [
    "las/simple.las", "las/1815.las", "las/test1_4.las", "las/simple1_4.las",
    "las/simple1_3.las", "las/gib_las_col.las", "las/liblas_1.0_1.las", "las/Example.las",
    "las/extra-bytes.las", "las/autzen-bmx-2010.las", "las/gps-time-nan.las",
    "las/epsg_4326.las", "las/5points_14.las", "las/vegetation_1_3.las",
]
# Byte offset of GPS time and RGB inside the record, per point format.
GPS_AT = {1: 20, 3: 20, 4: 20, 5: 20, 6: 22, 7: 22, 8: 22, 9: 22, 10: 22}
RGB_AT = {2: 20, 3: 28, 5: 28, 7: 30, 8: 30, 10: 30}


def read_header(data):
    minor = data[25]
    offset_to_points, = struct.unpack_from("<I", data, 96)
    fmt = data[104] & 0x3F
    rec_len, = struct.unpack_from("<H", data, 105)
    count, = struct.unpack_from("<I", data, 107)
    if minor >= 4:
        count64, = struct.unpack_from("<Q", data, 247)
        count = count64 or count
    scale = struct.unpack_from("<3d", data, 131)
    offset = struct.unpack_from("<3d", data, 155)
    return dict(minor=minor, start=offset_to_points, fmt=fmt, rec_len=rec_len,
                count=count, scale=scale, offset=offset)


def decode(data, h, i):
    base = h["start"] + i * h["rec_len"]
    X, Y, Z, intensity = struct.unpack_from("<3iH", data, base)
    fmt = h["fmt"]
    if fmt >= 6:
        b = data[base + 14]
        ret, nret = b & 15, b >> 4
        cls = data[base + 16]
    else:
        b = data[base + 14]
        ret, nret = b & 7, (b >> 3) & 7
        cls = data[base + 15] & 31
    gps = struct.unpack_from("<d", data, base + GPS_AT[fmt])[0] if fmt in GPS_AT else None
    rgb = struct.unpack_from("<3H", data, base + RGB_AT[fmt]) if fmt in RGB_AT else None
    xyz = [v * s + o for v, s, o in zip((X, Y, Z), h["scale"], h["offset"])]
    return xyz, intensity, ret, nret, cls, gps, rgb


def close(a, b):
    return a == b or abs(a - b) <= 1e-9 * max(1.0, abs(a), abs(b))


def check_file(info, path):
    data = open(path, "rb").read()
    h = read_header(data)
    n = min(h["count"], 2000)
    out = subprocess.run([info, "--points", "0:%d" % n, path], capture_output=True,
                         text=True, check=True).stdout.splitlines()
    expect_header = ("x,y,z,intensity,return_number,number_of_returns,classification,"
                     "gps_time,red,green,blue")
    if out[0] != expect_header:
        return "%s: CSV header %r" % (path, out[0])
    if len(out) != n + 1:
        return "%s: %d CSV rows, expected %d" % (path, len(out) - 1, n)
    for i in range(n):
        xyz, inten, ret, nret, cls, gps, rgb = decode(data, h, i)
        f = out[i + 1].split(",")
        if len(f) != 11:
            return "%s row %d: %d fields" % (path, i, len(f))
        for k in range(3):
            if not close(float(f[k]), xyz[k]):
                return "%s row %d: coordinate %d is %s, expected %r" % (path, i, k, f[k], xyz[k])
        if (int(f[3]), int(f[4]), int(f[5]), int(f[6])) != (inten, ret, nret, cls):
            return "%s row %d: %s vs %r" % (path, i, f[3:7], (inten, ret, nret, cls))
        if gps is None:
            if f[7] != "":
                return "%s row %d: gps_time %r for a format without it" % (path, i, f[7])
        elif math.isnan(gps):
            if f[7] != "nan":
                return "%s row %d: gps_time %r, expected nan" % (path, i, f[7])
        elif not close(float(f[7]), gps):
            return "%s row %d: gps_time %s, expected %r" % (path, i, f[7], gps)
        if rgb is None:
            if f[8:] != ["", "", ""]:
                return "%s row %d: colour %r for a format without it" % (path, i, f[8:])
        elif tuple(int(v) for v in f[8:]) != rgb:
            return "%s row %d: colour %r, expected %r" % (path, i, f[8:], rgb)
    js = json.loads(subprocess.run([info, "--json", path], capture_output=True, text=True,
                                   check=True).stdout)
    if js["point_count"] != h["count"] or js["point_format"] != h["fmt"]:
        return "%s: json count/format %r/%r" % (path, js["point_count"], js["point_format"])
    if js["record_length"] != h["rec_len"] or tuple(js["scale"]) != h["scale"]:
        return "%s: json record_length/scale %r %r" % (path, js["record_length"], js["scale"])
    # Actual bounds from every point, independently.
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for i in range(h["count"]):
        xyz = decode(data, h, i)[0]
        lo = [min(a, b) for a, b in zip(lo, xyz)]
        hi = [max(a, b) for a, b in zip(hi, xyz)]
    for k in range(3):
        if h["count"] and not (close(js["actual_min"][k], lo[k]) and
                               close(js["actual_max"][k], hi[k])):
            return "%s: actual bounds %r %r, expected %r %r" % (
                path, js["actual_min"], js["actual_max"], lo, hi)
    return None


def main():
    info, data_dir = sys.argv[1], sys.argv[2]
    if not os.path.isdir(data_dir):
        print("SKIPPED: shared data folder %s is absent" % data_dir)
        return 77
    failures = 0
    for rel in FILES:
        problem = check_file(info, os.path.join(data_dir, rel))
        if problem:
            print("MISMATCH", problem)
            failures += 1
        else:
            print("ok", rel)
    print("%d passed, %d failed" % (len(FILES) - failures, failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
