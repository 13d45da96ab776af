"""Minimal safetensors reader/writer (numpy), so the tools need no extra package.

Layout: u64 little-endian header length, a JSON header
{name: {"dtype", "shape", "data_offsets": [begin, end]}, "__metadata__": {str: str}}
padded with spaces to a multiple of 8 bytes, then the raw little-endian tensor data.
"""
import json
import struct

import numpy as np

DTYPES = {
    "F64": np.float64, "F32": np.float32, "F16": np.float16,
    "I64": np.int64, "I32": np.int32, "I16": np.int16, "I8": np.int8,
    "U64": np.uint64, "U32": np.uint32, "U16": np.uint16, "U8": np.uint8, "BOOL": np.bool_,
}
NAMES = {np.dtype(v).str: k for k, v in DTYPES.items()}


class SafetensorsError(ValueError):
    pass


def dtype_name(array):
    key = np.dtype(array.dtype).newbyteorder("<").str
    if key not in NAMES:
        raise SafetensorsError("unsupported dtype %s" % array.dtype)
    return NAMES[key]


def save(path, tensors, metadata=None):
    """Writes an ordered mapping name -> numpy array; metadata values must be strings."""
    header = {}
    offset = 0
    blobs = []
    for name, array in tensors.items():
        array = np.asarray(array, order="C")  # (ascontiguousarray would make scalars 1-D)
        dt = dtype_name(array)
        data = array.astype(array.dtype.newbyteorder("<"), copy=False).tobytes()
        header[name] = {"dtype": dt, "shape": list(array.shape),
                        "data_offsets": [offset, offset + len(data)]}
        blobs.append(data)
        offset += len(data)
    if metadata:
        for k, v in metadata.items():
            if not isinstance(k, str) or not isinstance(v, str):
                raise SafetensorsError("metadata %r: keys and values must be strings" % (k,))
        header["__metadata__"] = dict(metadata)
    text = json.dumps(header, separators=(",", ":")).encode("utf-8")
    text += b" " * ((8 - len(text) % 8) % 8)
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)))
        f.write(text)
        for b in blobs:
            f.write(b)


def load(path):
    """Returns (dict name -> numpy array in file order, metadata dict)."""
    with open(path, "rb") as f:
        raw = f.read()
    if len(raw) < 8:
        raise SafetensorsError("%s: file too short for a safetensors header" % path)
    (n,) = struct.unpack("<Q", raw[:8])
    if 8 + n > len(raw):
        raise SafetensorsError("%s: header length %d exceeds file size %d" % (path, n, len(raw)))
    try:
        header = json.loads(raw[8:8 + n].decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise SafetensorsError("%s: header is not valid JSON (%s)" % (path, e))
    meta = header.pop("__metadata__", {}) or {}
    data = memoryview(raw)[8 + n:]
    out = {}
    for name, info in header.items():
        if info["dtype"] not in DTYPES:
            raise SafetensorsError("%s: tensor %s has unsupported dtype %s" % (path, name, info["dtype"]))
        begin, end = info["data_offsets"]
        dt = np.dtype(DTYPES[info["dtype"]]).newbyteorder("<")
        count = int(np.prod(info["shape"])) if info["shape"] else 1
        if end > len(data) or end - begin != count * dt.itemsize:
            raise SafetensorsError("%s: tensor %s has inconsistent data offsets" % (path, name))
        out[name] = np.frombuffer(data[begin:end], dtype=dt).reshape(info["shape"]).copy()
    return out, meta
