#!/usr/bin/env python3
"""Writes the PTv3 golden fixtures under tests/fixtures/ptv3/ with tools/ptv3_reference.py.

    /usr/bin/python3 tools/make_ptv3_fixtures.py [OUT_DIR]      (default tests/fixtures/ptv3)

- small/: a tiny config with committed seeded weights, two clouds in one batch, logits and a
  trace of intermediate tensors (same key names as the shared ptv3-small fixture), plus an
  input with duplicate voxels.
- paper/: the paper's config; the weights are not committed but generated from their names
  by the hash generator of `paper_weight` (paper/README.md defines it for the C++ side).

Logits are computed in float64 and stored as float32. Deterministic: same output every run.
Needs Debian's python3-torch and python3-numpy (run with /usr/bin/python3).
"""
import json
import math
import os
import re
import sys

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ptv3_reference as ref  # noqa: E402
import safetensors_io as st  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_OUT = os.path.join(ROOT, "tests", "fixtures", "ptv3")
GRID = 0.02
SIGMA = 0.15

SMALL_CONFIG = ref.named_config("tiny")
PAPER_CONFIG = ref.named_config("paper")
PAPER_PARAMETERS = 46150402

# traced keys written to small/trace.safetensors (the shared fixture's set, plus the sub-ops
# of the first block of the finest decoder stage)
TRACE_RE = re.compile(
    r"^(input|logits|embedding|embedding\.stem\.conv|enc\.enc\d+|enc\.enc\d+\.down|enc\.enc\d+\.block\d+|"
    r"dec\.dec\d+|dec\.dec\d+\.up|dec\.dec\d+\.block\d+|"
    r"enc\.enc0\.block0\.(cpe|cpe\.\d|norm1|attn|norm2|mlp)|"
    r"dec\.dec[03]\.block0\.(cpe|cpe\.\d|norm1|attn|norm2|mlp))(/.*)?$")


# ----------------------------------------------------------------------------- weight generator

M64 = (1 << 64) - 1
GOLDEN = 0x9E3779B97F4A7C15


def fnv1a64(text):
    h = 0xCBF29CE484222325
    for byte in text.encode("utf-8"):
        h ^= byte
        h = (h * 0x100000001B3) & M64
    return h


def splitmix64(z):
    """Vectorized over uint64 arrays, 64-bit wrapping."""
    z = z + np.uint64(GOLDEN)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def uniform24(name, count):
    """u_i in [0, 1) with 24 bits: splitmix64(fnv1a64(name) ^ (i * GOLDEN)) >> 40, / 2^24."""
    with np.errstate(over="ignore"):
        i = np.arange(count, dtype=np.uint64)
        z = np.uint64(fnv1a64(name)) ^ (i * np.uint64(GOLDEN))
        bits = splitmix64(z) >> np.uint64(40)
    return bits.astype(np.float64) / float(1 << 24)


def weight_kind(name, shapes):
    """The generator's class of a state_dict entry (paper/README.md lists the rules)."""
    if name.endswith("num_batches_tracked"):
        return "counter"
    if name.endswith("running_mean"):
        return "running_mean"
    if name.endswith("running_var"):
        return "running_var"
    stem, leaf = name.rsplit(".", 1)
    weight_ndim = len(shapes.get(stem + ".weight", ()))
    if leaf == "weight":
        return "norm_weight" if weight_ndim == 1 else "dense_weight"
    if leaf == "bias":
        return "norm_bias" if weight_ndim == 1 else "dense_bias"
    raise ValueError("no generator rule for %s" % name)


def paper_weight(name, shape, kind):
    """One tensor of the generated weights (float32, or int64 zeros for counters)."""
    count = int(np.prod(shape)) if len(shape) else 1
    if kind == "counter":
        return np.zeros(shape, dtype=np.int64)
    u = uniform24(name, count)
    s = 2.0 * u - 1.0
    if kind == "dense_weight":
        fan_in = int(np.prod(shape[1:]))
        v = s * (1.0 / math.sqrt(fan_in))
    elif kind == "dense_bias":
        v = s * 0.02
    elif kind == "norm_weight":
        v = 1.0 + 0.1 * s
    elif kind == "norm_bias":
        v = 0.05 * s
    elif kind == "running_mean":
        v = 0.1 * s
    elif kind == "running_var":
        v = 0.5 + u
    else:
        raise ValueError(kind)
    return v.astype(np.float32).reshape(shape)


def generated_state_dict(model):
    shapes = {k: tuple(v.shape) for k, v in model.state_dict().items()}
    out = {}
    for name, shape in shapes.items():
        out[name] = paper_weight(name, shape, weight_kind(name, shapes))
    return out


def seeded_state_dict(model, seed, qk_gain=3.0):
    """Random weights for the small fixture: uniform +-1/sqrt(fan_in), q/k rows scaled,
    non-trivial norm affine and BatchNorm statistics."""
    g = torch.Generator().manual_seed(seed)

    def uni(shape, lo, hi):
        return (torch.rand(shape, generator=g, dtype=torch.float64) * (hi - lo) + lo)

    sd = model.state_dict()
    shapes = {k: tuple(v.shape) for k, v in sd.items()}
    out = {}
    for name, shape in shapes.items():
        kind = weight_kind(name, shapes)
        if kind == "counter":
            out[name] = np.zeros(shape, dtype=np.int64)
            continue
        if kind == "dense_weight":
            b = 1.0 / math.sqrt(int(np.prod(shape[1:])))
            v = uni(shape, -b, b)
            if name.endswith("attn.qkv.weight"):
                c = shape[1]
                v[:2 * c] *= qk_gain
        elif kind == "dense_bias":
            v = uni(shape, -0.05, 0.05)
        elif kind == "norm_weight":
            v = uni(shape, 0.7, 1.3)
        elif kind == "norm_bias":
            v = uni(shape, -0.2, 0.2)
        elif kind == "running_mean":
            v = uni(shape, -0.3, 0.3)
        else:
            v = uni(shape, 0.3, 2.0)
        out[name] = v.numpy().astype(np.float32)
    return out


# ----------------------------------------------------------------------------- synthetic scenes

def rot_z(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def surface_samples(rng, obj, count):
    if obj["kind"] == "sphere":
        v = rng.normal(size=(count, 3))
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        return np.asarray(obj["centre"]) + obj["size"] * v
    size = np.asarray(obj["size"], dtype=np.float64)
    areas = np.array([size[1] * size[2], size[0] * size[2], size[0] * size[1]] * 2)
    face = rng.choice(6, size=count, p=areas / areas.sum())
    p = (rng.random((count, 3)) - 0.5) * size
    axis = face % 3
    sign = np.where(face < 3, 0.5, -0.5)
    p[np.arange(count), axis] = sign * size[axis]
    return np.asarray(obj["centre"]) + p @ rot_z(obj.get("yaw_deg", 0.0)).T


def object_areas(obj):
    if obj["kind"] == "sphere":
        return 4 * math.pi * obj["size"] ** 2
    x, y, z = obj["size"]
    return 2 * (x * y + y * z + x * z)


def voxel_candidates(rng, scene):
    """One surface sample per 2 cm voxel of every object: (points, object index)."""
    pts, owner = [], []
    for k, obj in enumerate(scene):
        count = int(object_areas(obj) / GRID ** 2 * 12) + 100
        p = surface_samples(rng, obj, count)
        pts.append(p)
        owner.append(np.full(len(p), k))
    pts = np.concatenate(pts)
    owner = np.concatenate(owner)
    _, first = np.unique(np.floor(pts / GRID).astype(np.int64), axis=0, return_index=True)
    first = rng.permutation(first)
    return pts[first], owner[first]


def distinct_batch(rng, scenes, counts):
    """Clouds with `counts` points each, one point per voxel of the release's batch-wide grid."""
    cands = [voxel_candidates(rng, s) for s in scenes]
    for (p, _), n in zip(cands, counts):
        if len(p) < n:
            raise RuntimeError("scene too small for %d points (%d voxels)" % (n, len(p)))
    chosen = [np.arange(n) for n in counts]
    spare = [list(range(n, len(p))) for (p, _), n in zip(cands, counts)]
    for _ in range(100):
        coord = np.concatenate([cands[b][0][chosen[b]] for b in range(len(counts))]).astype(np.float32)
        batch = np.repeat(np.arange(len(counts)), counts)
        grid = ref.grid_coordinates(coord, GRID)
        key = np.concatenate([batch[:, None], grid], axis=1)
        _, first = np.unique(key, axis=0, return_index=True)
        dup = np.setdiff1d(np.arange(len(key)), first)
        if len(dup) == 0:
            owners = [cands[b][1][chosen[b]] for b in range(len(counts))]
            return coord, batch, owners
        starts = np.concatenate([[0], np.cumsum(counts)])
        for d in dup:
            b = int(np.searchsorted(starts, d, side="right") - 1)
            chosen[b][d - starts[b]] = spare[b].pop()
    raise RuntimeError("could not make distinct voxels")


def click_features(rng, coord, owner, positive_object, negative_object):
    pos = int(rng.choice(np.nonzero(owner == positive_object)[0]))
    neg = int(rng.choice(np.nonzero(owner == negative_object)[0]))
    d_pos = np.sum((coord - coord[pos]) ** 2, axis=1)
    d_neg = np.sum((coord - coord[neg]) ** 2, axis=1)
    feat = np.stack([np.exp(-d_pos / (2 * SIGMA ** 2)), np.exp(-d_neg / (2 * SIGMA ** 2))], axis=1)
    return feat.astype(np.float32), pos, neg


def make_input(seed, scenes, counts, clicks):
    """clicks[b] = (positive object, negative object) of cloud b. Returns coord, feat, info."""
    rng = np.random.default_rng(seed)
    coord, batch, owners = distinct_batch(rng, scenes, counts)
    feats, clouds = [], []
    start = 0
    for b, n in enumerate(counts):
        c = coord[start:start + n]
        f, pos, neg = click_features(rng, c.astype(np.float64), owners[b], *clicks[b])
        feats.append(f)
        clouds.append({
            "n": n, "first_point": start, "scene": scenes[b],
            "positive_click_index": start + pos, "positive_click_xyz": c[pos].tolist(),
            "negative_click_index": start + neg, "negative_click_xyz": c[neg].tolist()})
        start += n
    feat = np.concatenate(feats)
    n = len(coord)
    info = {
        "n": n, "offsets": np.cumsum(counts).tolist(), "seed": seed, "grid_size": GRID,
        "click_sigma_m": SIGMA, "clouds": clouds, "distinct_voxels": n, "duplicates_allowed": False,
        "file": "input.bin", "byte_order": "little",
        "arrays": [
            {"name": "coord", "dtype": "float32", "shape": [n, 3], "offset": 0,
             "meaning": "x, y, z in metres"},
            {"name": "feat", "dtype": "float32", "shape": [n, 2], "offset": 12 * n,
             "meaning": "channel 0 = positive click weight, channel 1 = negative click weight, "
                        "exp(-d^2 / (2 * 0.15^2)), d = distance to the cloud's click point"}],
        "batch": "cloud b holds rows [offsets[b-1], offsets[b]) (offsets are cumulative ends)",
        "grid_coord": "trunc((coord - coord.min over the whole batch) / grid_size) in float32",
    }
    return coord, feat, info


def write_input(d, stem, coord, feat, info):
    info = dict(info, file=stem + ".bin")
    with open(os.path.join(d, stem + ".bin"), "wb") as f:
        f.write(np.ascontiguousarray(coord, dtype="<f4").tobytes())
        f.write(np.ascontiguousarray(feat, dtype="<f4").tobytes())
    with open(os.path.join(d, stem + ".json"), "w") as f:
        json.dump(info, f, indent=1)
        f.write("\n")


def write_logits(path, logits):
    with open(path, "wb") as f:
        f.write(np.ascontiguousarray(logits, dtype="<f4").tobytes())


# ----------------------------------------------------------------------------- running

def run_both(weights, config, coord, feat, offsets):
    """Logits in float64 (the fixture) and float32 (for the recorded difference), and the trace."""
    m64 = ref.load_model(weights, config, torch.float64)
    l64, trace = ref.run_with_trace(m64, coord, feat, offsets=offsets)
    m32 = ref.load_model(weights, config, torch.float32)
    with torch.no_grad():
        l32 = m32(coord, feat, offsets=offsets)
    l64 = l64.numpy()
    diff = float(np.abs(l64 - l32.numpy().astype(np.float64)).max())
    return l64.astype(np.float32), trace, diff


def stats(a):
    a = np.asarray(a, dtype=np.float64)
    return {"mean": float(a.mean()), "std": float(a.std()), "min": float(a.min()), "max": float(a.max())}


def stage_summary(trace, config):
    out = {}
    for k, v in trace.items():
        if k.endswith("/feat") and re.match(r"^(embedding|enc\.enc\d+|dec\.dec\d+)/feat$", k):
            out[k] = dict(rows=int(v.shape[0]), channels=int(v.shape[1]), **stats(v))
    for k, v in trace.items():
        if k.endswith("/grid_coord"):
            out[k.replace("/grid_coord", "/points")] = int(v.shape[0])
    out["logits"] = stats(trace["logits"])
    return out


def degenerate_check(name, logits):
    cls = np.argmax(logits, axis=1)
    counts = np.bincount(cls, minlength=logits.shape[1]).tolist()
    std = float(np.std(logits[:, 0] - logits[:, 1]))
    ok = min(counts) > 0 and std > 1e-3
    print("%s: class counts %s, std of logit difference %.4f%s" % (name, counts, std, "" if ok else "  DEGENERATE"))
    return {"class_counts": counts, "logit_difference_std": std}


def build_small(out):
    d = os.path.join(out, "small")
    os.makedirs(d, exist_ok=True)
    config = SMALL_CONFIG
    model = ref.PTv3(config)
    weights = seeded_state_dict(model, seed=1)
    meta = {"config": json.dumps(config), "format": "pointgauss-ptv3",
            "source": "tools/make_ptv3_fixtures.py seeded_state_dict(seed=1, qk_gain=3)"}
    st.save(os.path.join(d, "weights.safetensors"), weights, meta)

    # two clouds overlapping in space (a conv or window that crossed clouds would show)
    scene_a = [
        {"name": "crate", "kind": "box", "centre": [0.0, 0.0, 0.1], "size": [0.3, 0.25, 0.25], "yaw_deg": 20.0},
        {"name": "ball", "kind": "sphere", "centre": [0.25, 0.15, 0.1], "size": 0.1, "yaw_deg": 0.0}]
    scene_b = [
        {"name": "post", "kind": "box", "centre": [0.12, 0.05, 0.12], "size": [0.1, 0.1, 0.35], "yaw_deg": -35.0},
        {"name": "pebble", "kind": "sphere", "centre": [0.28, -0.08, 0.07], "size": 0.07, "yaw_deg": 0.0}]
    coord, feat, info = make_input(7, [scene_a, scene_b], [700, 300], [(0, 1), (1, 0)])
    logits, trace, diff = run_both(weights, config, coord, feat, info["offsets"])
    info["logits_fp32_vs_fp64_max_abs"] = diff
    write_input(d, "input", coord, feat, info)
    write_logits(os.path.join(d, "logits.bin"), logits)
    kept = {}
    for k, v in trace.items():
        if TRACE_RE.match(k.split("/")[0]) or k in ("logits",) or k.startswith("input/"):
            kept[k] = v.astype(np.float32) if v.dtype == np.float64 else v
    kept["logits"] = logits
    st.save(os.path.join(d, "trace.safetensors"), kept,
            {"config": json.dumps(config), "computed_in": "float64, stored as float32"})
    check = degenerate_check("small", logits)

    # the release's order shuffle, pinned: one permutation of the four orders per level
    perms = [[3, 1, 0, 2], [1, 0, 3, 2], [2, 3, 1, 0], [0, 2, 3, 1], [3, 2, 1, 0]]
    m64 = ref.load_model(weights, config, torch.float64)
    with torch.no_grad():
        plogits = m64(coord, feat, offsets=info["offsets"], perms=perms).numpy().astype(np.float32)
    write_logits(os.path.join(d, "perm_logits.bin"), plogits)
    with open(os.path.join(d, "perm.json"), "w") as f:
        json.dump({"input": "input.bin", "perms": perms, "logits": "perm_logits.bin",
                   "meaning": "level l's code rows are level l-1's rows permuted by perms[l] "
                              "(level 0: the config's order list); block i of a level uses row i % 4",
                   "max_abs_diff_to_unpermuted": float(np.abs(plogits - logits).max())}, f, indent=1)
        f.write("\n")

    # duplicates: 120 extra points dropped into occupied voxels of both clouds
    rng = np.random.default_rng(11)
    grid = ref.grid_coordinates(coord, GRID)
    lo = coord.min(axis=0).astype(np.float64)
    offsets = info["offsets"]
    starts = [0] + offsets[:-1]
    parts_c, parts_f, dup_of = [], [], []
    for b in range(len(offsets)):
        rows = np.arange(starts[b], offsets[b])
        pick = rng.choice(rows, size=60 if b == 0 else 60, replace=False)
        # a point strictly inside the voxel of the picked point
        jitter = rng.uniform(0.2, 0.8, size=(len(pick), 3))
        extra = (lo + (grid[pick] + jitter) * GRID).astype(np.float32)
        c = np.concatenate([coord[rows], extra])
        f = np.concatenate([feat[rows], rng.random((len(pick), 2)).astype(np.float32)])
        perm = rng.permutation(len(c))
        parts_c.append(c[perm])
        parts_f.append(f[perm])
        dup_of.append(len(pick))
    dcoord = np.concatenate(parts_c)
    dfeat = np.concatenate(parts_f)
    doffsets = np.cumsum([len(p) for p in parts_c]).tolist()
    dgrid = ref.grid_coordinates(dcoord, GRID)
    dbatch = np.repeat(np.arange(len(doffsets)), np.diff([0] + doffsets))
    distinct = len(np.unique(np.concatenate([dbatch[:, None], dgrid], axis=1), axis=0))
    assert distinct == len(coord), (distinct, len(coord))
    dlogits, _, ddiff = run_both(weights, config, dcoord, dfeat, doffsets)
    dinfo = dict(info, n=len(dcoord), offsets=doffsets, distinct_voxels=distinct, duplicates_allowed=True,
                 seed=11, clouds=None, logits_fp32_vs_fp64_max_abs=ddiff,
                 duplicates="the clouds of input.bin with 60 points each added inside occupied voxels "
                            "(random features), rows shuffled within each cloud; the network sees the "
                            "lowest-index point of every (cloud, voxel) and every point gets its voxel's logits")
    dinfo["arrays"] = [dict(a) for a in info["arrays"]]
    dinfo["arrays"][0]["shape"] = [len(dcoord), 3]
    dinfo["arrays"][1]["shape"] = [len(dcoord), 2]
    dinfo["arrays"][1]["offset"] = 12 * len(dcoord)
    write_input(d, "dup_input", dcoord, dfeat, dinfo)
    write_logits(os.path.join(d, "dup_logits.bin"), dlogits)

    summary = {"config": config, "parameters": ref.count_parameters(model), "stages": stage_summary(trace, config),
               "logits_fp32_vs_fp64_max_abs": diff, "dup_logits_fp32_vs_fp64_max_abs": ddiff,
               "logits_check": check, "trace_entries": len(kept)}
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")
    return summary


def paper_scene_one():
    return [
        {"name": "crate", "kind": "box", "centre": [-0.35, -0.2, 0.2], "size": [0.5, 0.4, 0.4], "yaw_deg": 0.0},
        {"name": "tower", "kind": "box", "centre": [0.45, 0.3, 0.35], "size": [0.25, 0.25, 0.7], "yaw_deg": 30.0},
        {"name": "ball", "kind": "sphere", "centre": [0.35, -0.4, 0.25], "size": 0.22, "yaw_deg": 0.0},
        {"name": "pebble", "kind": "sphere", "centre": [-0.3, 0.45, 0.12], "size": 0.12, "yaw_deg": 0.0}]


def build_paper(out):
    d = os.path.join(out, "paper")
    os.makedirs(d, exist_ok=True)
    config = PAPER_CONFIG
    model = ref.PTv3(config)
    nparams = ref.count_parameters(model)
    if nparams != PAPER_PARAMETERS:
        raise RuntimeError("paper config has %d parameters, expected %d" % (nparams, PAPER_PARAMETERS))
    weights = generated_state_dict(model)
    with open(os.path.join(d, "config.json"), "w") as f:
        json.dump(config, f, indent=1)
        f.write("\n")

    # probes for the C++ generator: per tensor its kind, shape, first values and sum
    shapes = {k: tuple(v.shape) for k, v in weights.items()}
    probes = []
    for k, v in weights.items():
        flat = v.reshape(-1)
        probes.append({"name": k, "kind": weight_kind(k, shapes), "shape": list(v.shape),
                       "first": [float(x) if v.dtype != np.int64 else int(x) for x in flat[:3]],
                       "last": float(flat[-1]) if v.dtype != np.int64 else int(flat[-1]),
                       "sum": float(flat.astype(np.float64).sum())})
    with open(os.path.join(d, "weights_probe.json"), "w") as f:
        json.dump({"entries": len(probes), "parameters": nparams, "tensors": probes}, f, indent=0)
        f.write("\n")

    runs = {}
    scene_b = [
        {"name": "cabinet", "kind": "box", "centre": [0.0, 0.0, 0.3], "size": [0.3, 0.25, 0.6], "yaw_deg": 15.0},
        {"name": "globe", "kind": "sphere", "centre": [0.3, 0.2, 0.15], "size": 0.12, "yaw_deg": 0.0}]
    scene_c = [
        {"name": "stool", "kind": "box", "centre": [0.1, 0.1, 0.15], "size": [0.2, 0.2, 0.3], "yaw_deg": -20.0},
        {"name": "orb", "kind": "sphere", "centre": [-0.1, 0.2, 0.1], "size": 0.09, "yaw_deg": 0.0}]
    for stem, seed, scenes, counts, clicks in [
            ("input", 3, [paper_scene_one()], [3000], [(0, 2)]),
            ("input2", 5, [scene_b, scene_c], [1000, 500], [(0, 1), (1, 0)])]:
        coord, feat, info = make_input(seed, scenes, counts, clicks)
        logits, trace, diff = run_both(weights, config, coord, feat, info["offsets"])
        info["logits_fp32_vs_fp64_max_abs"] = diff
        write_input(d, stem, coord, feat, info)
        logits_name = stem.replace("input", "logits") + ".bin"
        write_logits(os.path.join(d, logits_name), logits)
        runs[stem] = {"logits": logits_name, "offsets": info["offsets"],
                      "logits_fp32_vs_fp64_max_abs": diff,
                      "logits_check": degenerate_check("paper " + stem, logits),
                      "stages": stage_summary(trace, config)}
    summary = {"parameters": nparams, "state_dict_entries": len(weights), "runs": runs}
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")
    return summary


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else DEFAULT_OUT
    torch.set_num_threads(min(2, torch.get_num_threads()))
    s = build_small(out)
    print("small: %d parameters, fp32 vs fp64 logits %.3e" % (s["parameters"], s["logits_fp32_vs_fp64_max_abs"]))
    p = build_paper(out)
    for k, r in p["runs"].items():
        print("paper %s: fp32 vs fp64 logits %.3e" % (k, r["logits_fp32_vs_fp64_max_abs"]))


if __name__ == "__main__":
    main()
