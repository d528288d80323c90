"""Prints how much of a preview's width and height its surface spans: the share of columns and
of rows between the first and last pixel that differ from the background (8-bit RGB PNG)."""
import struct
import sys
import zlib

BACKGROUND = (44, 48, 58)  # kBackground in include/rangefuse/render/Render.h


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else (b if pb <= pc else c)


def read_rgb_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour == 2, f"{path}: not 8-bit RGB"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride, rows, prev = zlib.decompress(idat), 3 * width, [], bytearray(3 * width)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 3] if i >= 3 else 0
            b, c = prev[i], prev[i - 3] if i >= 3 else 0
            line[i] = (line[i] + [0, a, b, (a + b) // 2, paeth(a, b, c)][kind]) & 255
        rows.append(line)
        prev = line
    return width, height, rows


width, height, rows = read_rgb_png(sys.argv[1])
xs, ys = [], []
for y, line in enumerate(rows):
    for x in range(width):
        if tuple(line[3 * x:3 * x + 3]) != BACKGROUND:
            xs.append(x)
            ys.append(y)
if not xs:
    print("0 0")
else:
    print(f"{(max(xs) - min(xs) + 1) / width:.3f} {(max(ys) - min(ys) + 1) / height:.3f}")
