#!/usr/bin/env python3
"""Times a PTv3 forward of the plain-PyTorch reference (tools/ptv3_reference.py) on the CPU,
for comparison with `pointgauss bench ptv3` on the same input and weights.

    /usr/bin/python3 tools/bench_ptv3_torch.py --config paper|small [--input IN.bin] [--threads 2]

Weights are the name-hash generator of the paper fixture (the same values `bench ptv3
--model paper|small` builds); the input is coord f32 [N,3] then feat f32 [N,2].
The release's own model.py (spconv, torch_scatter) is not available here; this reference
computes the same function with dense PyTorch ops, so its time is a stand-in, not the
release's figure.
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_ptv3_fixtures as fx  # noqa: E402
import ptv3_reference as ref  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--config", default="paper", choices=["paper", "small"])
    ap.add_argument("--input", default=os.path.join(fx.ROOT, "..", "shared", "fixtures", "ptv3-small", "input.bin"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    torch.set_num_threads(a.threads)
    config = ref.named_config(a.config)
    model = ref.PTv3(config)
    weights = fx.generated_state_dict(model)
    model = ref.load_model(weights, config, torch.float32)
    raw = np.fromfile(a.input, dtype="<f4")
    n = raw.size // (3 + config["in_channels"])
    coord = raw[: 3 * n].reshape(n, 3)
    feat = raw[3 * n:].reshape(n, config["in_channels"])
    times = []
    with torch.no_grad():
        for r in range(a.repeats + 1):
            t0 = time.perf_counter()
            model(coord, feat, offsets=[n])
            if r:
                times.append(time.perf_counter() - t0)
    print("%s config, %d points, %d threads: median %.3f s over %d runs (%s)" % (
        a.config, n, a.threads, statistics.median(times), len(times), ", ".join("%.3f" % t for t in times)))


if __name__ == "__main__":
    main()
