# SPDX-License-Identifier: MIT
# Decodes an 8-bit RGB(A) PNG into rows of (r, g, b) tuples with the standard library
# only, for the headless render checks (check_view_survey.py, check_view_point_size.py).
import struct, zlib


def png(path):
    """RGB(A) rows of an 8-bit PNG, decoded here (no libraries)."""
    b = open(path, "rb").read()
    i, data, w, h, ct = 8, b"", 0, 0, 6
    while i < len(b):
        n, = struct.unpack(">I", b[i:i + 4])
        t, c = b[i + 4:i + 8], b[i + 8:i + 8 + n]
        if t == b"IHDR":
            w, h, _, ct = struct.unpack(">IIBB", c[:10])
        elif t == b"IDAT":
            data += c
        i += 12 + n
    raw, bpp = zlib.decompress(data), 4 if ct == 6 else 3
    stride, rows, prev = w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            up, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + up) & 255
            elif f == 3: line[x] = (line[x] + (a + up) // 2) & 255
            elif f == 4:
                p = a + up - c
                pa, pb, pc = abs(p - a), abs(p - up), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else up if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, [[tuple(r[x * bpp:x * bpp + 3]) for x in range(w)] for r in rows]
