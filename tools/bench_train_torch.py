#!/usr/bin/env python3
"""Times PTv3 training steps of the plain-PyTorch reference (tools/ptv3_reference.py) on the
CPU, for comparison with `pointgauss bench train` on the same config and input size.

    /usr/bin/python3 tools/bench_train_torch.py --config tiny|small|paper --input IN.bin
        [--channels 2] [--repeats 5] [--warmup 1] [--threads N] [--json]

IN.bin is coord f32 [N,3] then feat f32 [N,C] (e.g. /work/shared/fixtures/ptv3-small/input.bin).
One step, as `bench train` runs it: a training-mode forward (BatchNorm on batch statistics,
per-point drop path 0.3 spaced over the blocks as Pointcept does), mean cross-entropy over the
voxels with label 1 where feat[:,0] > 0.5, backward, AdamW (lr 1e-4, weight decay 0.05).
Weights are the name-hash generator of the paper fixture. The reference uses dense PyTorch ops
instead of spconv / torch_scatter, so its time stands in for the release's, it is not it.
"""
import argparse
import contextlib
import json
import os
import resource
import statistics
import sys
import time

import numpy as np
import torch
import torch.nn.functional as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_ptv3_fixtures as fx  # noqa: E402
import ptv3_reference as ref  # noqa: E402
from make_ptv3_train_fixture import training_batch_norm  # noqa: E402

DROP_PATH = 0.3
LR, WEIGHT_DECAY = 1e-4, 0.05


def drop_path(x, rate, training=True):
    """Pointcept's DropPath on a point cloud: whole rows kept with 1 - rate, scaled by 1/(1 - rate)."""
    if rate <= 0 or not training:
        return x
    keep = x.new_empty(x.shape[0], 1).bernoulli_(1 - rate)
    return x * keep / (1 - rate)


def train_block_forward(self, feat, conv_in, level, rec, name):
    """ref.Block.forward with drop path on the attention and MLP branches (self.drop_rate)."""
    h = self.cpe[2](self.cpe[1](self.cpe[0](conv_in, level.table3)))
    x = feat + h
    h = self.attn(self.norm1(x), level.order[self.order_index], level.segments[self.order_index])
    x = x + drop_path(h, self.drop_rate)
    return x + drop_path(self.mlp(self.norm2(x)), self.drop_rate)


@contextlib.contextmanager
def training_mode():
    """The reference looks batch_norm and Block.forward up at call time: swap in training variants."""
    saved = ref.batch_norm, ref.Block.forward
    ref.batch_norm, ref.Block.forward = training_batch_norm, train_block_forward
    try:
        yield
    finally:
        ref.batch_norm, ref.Block.forward = saved


def assign_drop_rates(model, config, rate):
    """Pointcept: linspace(0, rate, blocks) over the encoder in order, and over the decoder with each
    stage's slice reversed."""
    enc = torch.linspace(0, rate, sum(config["enc_depths"])).tolist()
    dec = torch.linspace(0, rate, sum(config["dec_depths"])).tolist()
    b = 0
    for s, depth in enumerate(config["enc_depths"]):
        for i in range(depth):
            getattr(getattr(model.enc, "enc%d" % s), "block%d" % i).drop_rate = enc[b]
            b += 1
    for s, depth in enumerate(config["dec_depths"]):
        first = sum(config["dec_depths"][:s])
        rates = dec[first:first + depth][::-1]
        for i in range(depth):
            getattr(getattr(model.dec, "dec%d" % s), "block%d" % i).drop_rate = rates[i]


def voxel_rows(coord, grid_size):
    """The input index of each voxel's point (the lowest index per voxel), as the reference keeps them."""
    grid = ref.grid_coordinates(coord, grid_size)
    _, first = np.unique(grid, axis=0, return_index=True)
    return np.sort(first)


def rss_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--config", default="small", choices=sorted(ref.NAMED_CONFIGS))
    ap.add_argument("--input", required=True)
    ap.add_argument("--channels", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--threads", type=int, default=torch.get_num_threads(),
                    help="torch intra-op threads (default: torch's own, %(default)s here; on a busy machine "
                         "more OpenMP threads than idle cores make a step several times slower)")
    ap.add_argument("--seed", type=int, default=1, help="drop path masks")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    if a.repeats < 1 or a.warmup < 0 or a.threads < 1 or a.channels < 1:
        ap.error("--repeats and --threads must be >= 1, --warmup >= 0, --channels >= 1")
    torch.set_num_threads(a.threads)
    torch.manual_seed(a.seed)

    config = ref.named_config(a.config)
    config["in_channels"] = a.channels
    raw = np.fromfile(a.input, dtype="<f4")
    if raw.size % (3 + a.channels):
        sys.exit("%s: %d floats is not a multiple of 3 + %d channels" % (a.input, raw.size, a.channels))
    n = raw.size // (3 + a.channels)
    coord = raw[: 3 * n].reshape(n, 3)
    feat = raw[3 * n:].reshape(n, a.channels)
    keep = torch.from_numpy(voxel_rows(coord, config["grid_size"]))
    labels = torch.from_numpy((feat[:, 0] > 0.5).astype(np.int64))[keep]

    model = ref.load_model(fx.generated_state_dict(ref.PTv3(config)), config, torch.float32)
    model.train()
    assign_drop_rates(model, config, DROP_PATH)
    opt = torch.optim.AdamW(model.parameters(), lr=LR, betas=(0.9, 0.999), eps=1e-8, weight_decay=WEIGHT_DECAY)
    rss_model = rss_mib()
    load_before = os.getloadavg()

    times = {"forward": [], "backward": [], "optimizer": [], "step": []}
    for r in range(a.warmup + a.repeats):
        t0 = time.perf_counter()
        opt.zero_grad(set_to_none=True)
        with training_mode():
            logits = model(coord, feat, offsets=[n])
        loss = F.cross_entropy(logits[keep], labels)  # one row per voxel
        t1 = time.perf_counter()
        loss.backward()
        t2 = time.perf_counter()
        opt.step()
        t3 = time.perf_counter()
        if r >= a.warmup:
            for k, dt in zip(times, (t1 - t0, t2 - t1, t3 - t2, t3 - t0)):
                times[k].append(1000.0 * dt)
    med = {k: statistics.median(v) for k, v in times.items()}
    out = {
        "config": a.config, "parameters": ref.count_parameters(model), "points": n, "voxels": int(keep.numel()),
        "positive_voxels": int(labels.sum()), "loss": float(loss), "repeats": a.repeats, "warmup": a.warmup,
        "step_ms": med["step"], "steps_per_s": 1000.0 / med["step"], "forward_ms": med["forward"],
        "backward_ms": med["backward"], "optimizer_ms": med["optimizer"],
        "step_ms_all": [round(t, 1) for t in times["step"]],
        "torch": torch.__version__, "threads": torch.get_num_threads(),
        "rss_after_model_mib": rss_model, "peak_rss_mib": rss_mib(),
        "load_average_1min": {"before": round(load_before[0], 2), "after": round(os.getloadavg()[0], 2)},
    }
    if a.json:
        print(json.dumps(out, indent=2))
        return
    print("torch %s on the CPU, %d thread(s); load average %.2f before, %.2f after" % (
        out["torch"], out["threads"], load_before[0], out["load_average_1min"]["after"]))
    print("config: %s (%d parameters), %d points, %d voxels (%d labelled 1), median of %d steps after %d warmup\n" % (
        a.config, out["parameters"], n, out["voxels"], out["positive_voxels"], a.repeats, a.warmup))
    for k in ("forward", "backward", "optimizer", "step"):
        print("%-10s %10.1f ms" % (k, med[k]))
    print("\n%.3f steps/s, %.0f points/s (steps: %s ms)" % (
        out["steps_per_s"], 1000.0 * n / med["step"], ", ".join("%.0f" % t for t in times["step"])))
    print("peak RSS %.1f MiB (%.1f MiB after building the model)" % (out["peak_rss_mib"], rss_model))


if __name__ == "__main__":
    main()
