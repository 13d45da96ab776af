#!/usr/bin/env python3
"""Checks tools/ptv3_reference.py against a golden PTv3 fixture and prints a table.

Every tensor of the fixture's trace.safetensors is compared: float tensors by max abs error
and max abs error relative to the tensor's max |value|, integer tensors (voxels, codes,
orders, inverses, pooling inverse, padding) exactly. Exit status 1 if any integer tensor
differs or the logits' relative error exceeds --tol.

    /usr/bin/python3 tools/check_ptv3_reference.py [FIXTURE_DIR] [--input STEM] [--double] [--tol 1e-5]

FIXTURE_DIR defaults to /work/shared/fixtures/ptv3-small; it also accepts
tests/fixtures/ptv3/small (config in the weights' __metadata__, offsets in input.json) and
tests/fixtures/ptv3/paper (weights generated from config.json); --input picks input2 or dup_input.
"""
import argparse
import json
import os
import sys

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ptv3_reference as ref  # noqa: E402
import safetensors_io as st  # noqa: E402

DEFAULT_DIR = "/work/shared/fixtures/ptv3-small"


def load_fixture(d, stem="input"):
    wpath = os.path.join(d, "weights.safetensors")
    if os.path.exists(wpath):
        weights, meta = st.load(wpath)
        config = json.loads(meta["config"])
    else:  # tests/fixtures/ptv3/paper: weights generated from their names
        import make_ptv3_fixtures as gen
        with open(os.path.join(d, "config.json")) as f:
            config = json.load(f)
        weights = gen.generated_state_dict(ref.PTv3(config))
    with open(os.path.join(d, stem + ".json")) as f:
        info = json.load(f)
    if "grid_size" not in config:
        config["grid_size"] = info.get("grid_size", 0.02)
    n = info["n"]
    cin = config["in_channels"]
    raw = np.fromfile(os.path.join(d, stem + ".bin"), dtype="<f4")
    coord = raw[:3 * n].reshape(n, 3)
    feat = raw[3 * n:3 * n + cin * n].reshape(n, cin)
    offsets = info.get("offsets", [n])
    logits = np.fromfile(os.path.join(d, stem.replace("input", "logits") + ".bin"), dtype="<f4").reshape(n, -1)
    trace_path = os.path.join(d, "trace.safetensors")
    trace = st.load(trace_path)[0] if os.path.exists(trace_path) and stem == "input" else {}
    return weights, config, coord, feat, offsets, logits, trace


def compare(name, got, want):
    if got is None:
        return name, "missing", None, None, False
    got = np.asarray(got)
    if got.shape != want.shape:
        return name, "shape %s vs %s" % (got.shape, want.shape), None, None, False
    if np.issubdtype(want.dtype, np.integer):
        bad = int(np.count_nonzero(got.astype(np.int64) != want.astype(np.int64)))
        return name, "exact" if bad == 0 else "%d differ" % bad, 0.0 if bad == 0 else None, None, bad == 0
    err = np.abs(got.astype(np.float64) - want.astype(np.float64))
    amax = float(err.max()) if err.size else 0.0
    scale = float(np.abs(want).max()) if want.size else 0.0
    rel = amax / scale if scale > 0 else amax
    return name, "float", amax, rel, True


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("fixture", nargs="?", default=DEFAULT_DIR)
    ap.add_argument("--input", default="input", help="input stem: input, input2, dup_input (logits: logits*.bin)")
    ap.add_argument("--double", action="store_true", help="run the reference in float64")
    ap.add_argument("--tol", type=float, default=1e-5, help="max relative logits error")
    args = ap.parse_args()
    if not os.path.isdir(args.fixture):
        print("%s: fixture directory not found" % args.fixture, file=sys.stderr)
        return 2
    torch.set_num_threads(min(2, torch.get_num_threads()))
    weights, config, coord, feat, offsets, logits, trace = load_fixture(args.fixture, args.input)
    model = ref.load_model(weights, config, torch.float64 if args.double else torch.float32)
    got_logits, got = ref.run_with_trace(model, coord, feat, offsets=offsets)
    got["logits"] = got_logits.numpy()
    names = list(trace.keys()) if trace else ["logits"]
    if "logits" not in trace:
        trace["logits"] = logits
        names.append("logits") if "logits" not in names else None
    ok = True
    print("%-44s %-16s %12s %12s" % ("tensor", "kind", "max abs", "max rel"))
    worst = 0.0
    for name in names:
        want = trace[name]
        n, kind, amax, rel, good = compare(name, got.get(name), want)
        ok &= good
        if rel is not None:
            worst = max(worst, rel)
        print("%-44s %-16s %12s %12s" % (n, kind, "-" if amax is None else "%.3e" % amax,
                                         "-" if rel is None else "%.3e" % rel))
    _, _, lamax, lrel, _ = compare("logits", got_logits.numpy(), logits)
    print("logits.bin: max abs %.3e, max rel %.3e (tolerance %.1e); worst traced rel %.3e"
          % (lamax, lrel, args.tol, worst))
    if lrel > args.tol:
        ok = False
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
