#!/usr/bin/env python3
"""Set one key of a PointGauss model's config (the safetensors header's __metadata__.config JSON).

usage: set_model_config.py MODEL.safetensors KEY JSON_VALUE OUT.safetensors
The tensors are copied byte for byte; OUT must not be MODEL (inputs are never overwritten).
"""
import json
import os
import struct
import sys


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    src, key, value, out = sys.argv[1:]
    if os.path.abspath(src) == os.path.abspath(out):
        sys.exit(f"{out}: would overwrite the input")
    data = open(src, "rb").read()
    (n,) = struct.unpack("<Q", data[:8])
    header = json.loads(data[8:8 + n])
    meta = header.setdefault("__metadata__", {})
    config = json.loads(meta.get("config", "{}"))
    config[key] = json.loads(value)
    meta["config"] = json.dumps(config, sort_keys=True, separators=(",", ":"))
    text = json.dumps(header, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 8)  # keep the tensors 8-byte aligned
    tmp = out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + data[8 + n:])
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
