#!/usr/bin/env python3
"""Writes a SOG v1 scene (unbundled: meta.json and WebP images) from a binary float PLY.

splat-transform now writes only v2, yet v1 files are still published and read (its
read-sog-v1); this makes a v1 fixture the way the v1 writer laid it out: means as 16-bit
lerps of sign(x)*ln(|x|+1), quaternions as the smallest three with the mode in alpha,
scales, colours and the opacity logit as 8-bit lerps between per-channel mins and maxs,
and SH as a palette (here one entry per Gaussian) of 8-bit lerps between one min and max.
Images are encoded losslessly by cwebp (Debian's `webp` package).
    python3 tools/make_sog_v1.py IN.ply OUT_FOLDER
"""
import json
import math
import os
import struct
import subprocess
import sys
import tempfile


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    codes = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f",
             "double": "d"}
    names, fmt, count = [], "<", 0
    for line in data[:end].decode("ascii").splitlines():
        p = line.split()
        if p[:2] == ["element", "vertex"]:
            count = int(p[2])
        elif p[:1] == ["property"]:
            names.append(p[2])
            fmt += codes[p[1]]
    stride = struct.calcsize(fmt)
    rows = struct.iter_unpack(fmt, data[end:end + stride * count])
    cols = {n: [] for n in names}
    for r in rows:
        for n, v in zip(names, r):
            cols[n].append(v)
    return cols, count


def write_webp(folder, name, width, height, rgba):
    with tempfile.NamedTemporaryFile(suffix=".pam", delete=False) as f:
        f.write(b"P7\nWIDTH %d\nHEIGHT %d\nDEPTH 4\nMAXVAL 255\nTUPLTYPE RGB_ALPHA\nENDHDR\n" % (width, height))
        f.write(bytes(rgba))
        pam = f.name
    subprocess.run(["cwebp", "-quiet", "-lossless", "-exact", "-z", "9", pam, "-o", os.path.join(folder, name)],
                   check=True)
    os.unlink(pam)


def lerp_byte(v, lo, hi):
    return 0 if hi == lo else max(0, min(255, int(round(255 * (v - lo) / (hi - lo)))))


def main():
    src, out = sys.argv[1], sys.argv[2]
    cols, n = read_ply(src)
    os.makedirs(out, exist_ok=True)
    w = int(math.ceil(math.sqrt(n) / 4) * 4)
    h = int(math.ceil(n / w / 4) * 4)

    def image():
        return bytearray([0, 0, 0, 255] * (w * h))

    log_t = lambda x: math.copysign(math.log(abs(x) + 1), x)
    lo, hi = image(), image()
    mins = [min(log_t(v) for v in cols[a]) for a in "xyz"]
    maxs = [max(log_t(v) for v in cols[a]) for a in "xyz"]
    for i in range(n):
        for k, a in enumerate("xyz"):
            q = 0 if maxs[k] == mins[k] else int(round(65535 * (log_t(cols[a][i]) - mins[k]) / (maxs[k] - mins[k])))
            lo[i * 4 + k], hi[i * 4 + k] = q & 255, q >> 8
    write_webp(out, "means_l.webp", w, h, lo)
    write_webp(out, "means_u.webp", w, h, hi)

    quats = image()
    for i in range(n):
        q = [cols["rot_%d" % k][i] for k in range(4)]
        norm = math.sqrt(sum(c * c for c in q))
        q = [c / norm for c in q]
        largest = max(range(4), key=lambda k: abs(q[k]))
        if q[largest] < 0:
            q = [-c for c in q]
        others = [k for k in range(4) if k != largest]
        for j, k in enumerate(others):
            quats[i * 4 + j] = max(0, min(255, int(round(255 * (q[k] * math.sqrt(2) * 0.5 + 0.5)))))
        quats[i * 4 + 3] = 252 + largest
    write_webp(out, "quats.webp", w, h, quats)

    def lerp_image(names, alpha_name=None):
        img = image()
        keys = names + ([alpha_name] if alpha_name else [])
        lo_ = [min(cols[k]) for k in keys]
        hi_ = [max(cols[k]) for k in keys]
        for i in range(n):
            for c, k in enumerate(keys):
                img[i * 4 + c] = lerp_byte(cols[k][i], lo_[c], hi_[c])
        return img, lo_, hi_

    scales, s_lo, s_hi = lerp_image(["scale_0", "scale_1", "scale_2"])
    write_webp(out, "scales.webp", w, h, scales)
    sh0, c_lo, c_hi = lerp_image(["f_dc_0", "f_dc_1", "f_dc_2"], "opacity")
    write_webp(out, "sh0.webp", w, h, sh0)

    meta = {
        "means": {"shape": [n, 3], "dtype": "float32", "mins": mins, "maxs": maxs,
                  "files": ["means_l.webp", "means_u.webp"]},
        "scales": {"shape": [n, 3], "dtype": "float32", "mins": s_lo, "maxs": s_hi, "files": ["scales.webp"]},
        "quats": {"shape": [n, 4], "dtype": "uint8", "encoding": "quaternion_packed", "files": ["quats.webp"]},
        "sh0": {"shape": [n, 1, 4], "dtype": "float32", "mins": c_lo, "maxs": c_hi, "files": ["sh0.webp"]},
    }
    rest = sorted((k for k in cols if k.startswith("f_rest_")), key=lambda k: int(k[7:]))
    coeffs = len(rest) // 3
    if coeffs:
        r_lo = min(min(cols[k]) for k in rest)
        r_hi = max(max(cols[k]) for k in rest)
        rows = (n + 63) // 64
        palette = bytearray([0, 0, 0, 255] * (64 * coeffs * rows))
        labels = image()
        for i in range(n):
            labels[i * 4], labels[i * 4 + 1] = i & 255, i >> 8
            for j in range(coeffs):
                px = ((i // 64) * 64 * coeffs + (i % 64) * coeffs + j) * 4
                for c in range(3):
                    palette[px + c] = lerp_byte(cols[rest[c * coeffs + j]][i], r_lo, r_hi)
        write_webp(out, "shN_centroids.webp", 64 * coeffs, rows, palette)
        write_webp(out, "shN_labels.webp", w, h, labels)
        meta["shN"] = {"shape": [n, coeffs, 3], "dtype": "float32", "mins": r_lo, "maxs": r_hi, "quantization": 8,
                       "files": ["shN_centroids.webp", "shN_labels.webp"]}
    with open(os.path.join(out, "meta.json"), "w") as f:
        json.dump(meta, f)


if __name__ == "__main__":
    main()
