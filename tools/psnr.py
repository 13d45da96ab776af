#!/usr/bin/env python3
"""PSNR (dB) between the PNGs of two render folders, matched by name; prints one line per view
and the mean. 8-bit RGB/RGBA PNGs as `pointgauss render` writes them; plain standard library.
    python3 tools/psnr.py REFERENCE_DIR TEST_DIR
"""
import math
import os
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path + ": not a PNG"
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour in (2, 6), path + ": expected 8-bit RGB or RGBA"
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return [v for row in rows for i, v in enumerate(row) if i % channels < 3]


def psnr(a, b):
    mse = sum((x - y) ** 2 for x, y in zip(a, b)) / len(a)
    return float("inf") if mse == 0 else 10 * math.log10(255 ** 2 / mse)


def main():
    ref, test = sys.argv[1], sys.argv[2]
    names = sorted(n for n in os.listdir(ref) if n.endswith(".png") and "." not in n[:-4])
    values = []
    for n in names:
        v = psnr(read_png(os.path.join(ref, n)), read_png(os.path.join(test, n)))
        values.append(v)
        print("%s %.2f" % (n, v))
    print("mean %.2f dB over %d views" % (sum(values) / len(values), len(values)))


if __name__ == "__main__":
    main()
