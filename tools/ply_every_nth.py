#!/usr/bin/env python3
"""Writes every n-th vertex (from `first`) of a binary little-endian PLY with one vertex element.

Used to make small fixtures from benchmark scenes:
    python3 tools/ply_every_nth.py IN.ply OUT.ply N [FIRST]
"""
import struct
import sys

SIZES = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8}


def main():
    src, dst, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
    first = int(sys.argv[4]) if len(sys.argv) > 4 else 0
    data = open(src, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in lines:
        sys.exit(src + ": not a binary little-endian PLY")
    count, stride, out_lines = 0, 0, []
    for line in lines:
        parts = line.split()
        if parts[:2] == ["element", "vertex"]:
            count = int(parts[2])
            line = "element vertex %d"
        elif parts[:1] == ["element"]:
            sys.exit(src + ": only a vertex element is supported")
        elif parts[:1] == ["property"]:
            stride += SIZES[parts[1]]
        out_lines.append(line)
    rows = [data[end + i * stride:end + (i + 1) * stride] for i in range(first, count, n)]
    header = "\n".join(out_lines).replace("element vertex %d", "element vertex %d" % len(rows)) + "\n"
    with open(dst, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(b"".join(rows))


if __name__ == "__main__":
    main()
