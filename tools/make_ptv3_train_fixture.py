#!/usr/bin/env python3
"""Writes tests/fixtures/ptv3/train/: golden PTv3 training gradients from PyTorch autograd.

    /usr/bin/python3 tools/make_ptv3_train_fixture.py [OUT_DIR]   (default tests/fixtures/ptv3/train)

One training step's forward and backward of the tiny config with the committed weights of
tests/fixtures/ptv3/small/weights.safetensors (read, not copied) on two clouds of distinct
voxels, in float64, stored as float32:

- BatchNorm normalises with the batch statistics (biased variance) and updates its running
  statistics with momentum 0.01 (unbiased variance), as torch's BatchNorm1d in train();
  LayerNorm as at inference; no dropout, no drop path.
- loss = mean softmax cross-entropy over the points whose label is not -1; and again (as
  grads_lovasz.safetensors) with the Lovasz-softmax loss added (Berman et al.: per class present,
  errors |fg - p| sorted descending, dotted with the Lovasz gradient of the sorted foreground).

The script checks its own gradients against central finite differences of the float64
loss and fails if the worst relative error reaches 1e-5. Deterministic: same bytes every run.
Needs Debian's python3-torch and python3-numpy (run with /usr/bin/python3).
"""
import contextlib
import copy
import hashlib
import json
import os
import sys

import numpy as np
import torch
import torch.nn.functional as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_ptv3_fixtures as fx  # noqa: E402
import ptv3_reference as ref  # noqa: E402
import safetensors_io as st  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_OUT = os.path.join(ROOT, "tests", "fixtures", "ptv3", "train")
WEIGHTS = os.path.join(ROOT, "tests", "fixtures", "ptv3", "small", "weights.safetensors")
IGNORE = -1
IGNORE_FRACTION = 0.05
LABEL_RADIUS = 0.12  # label 1 inside this sphere around the cloud's positive click
FD_STEP = 1e-6
FD_LIMIT = 1e-5


# ----------------------------------------------------------------------------- training mode

def training_batch_norm(bn, x):
    """Batch statistics; running stats updated in place (torch's train() semantics)."""
    return F.batch_norm(x, bn.running_mean, bn.running_var, bn.weight, bn.bias, True, bn.momentum, bn.eps)


@contextlib.contextmanager
def training_mode():
    """ptv3_reference looks batch_norm up at call time: swap in the training variant."""
    saved = ref.batch_norm
    ref.batch_norm = training_batch_norm
    try:
        yield
    finally:
        ref.batch_norm = saved


def load_weights():
    tensors, meta = st.load(WEIGHTS)
    config = json.loads(meta["config"])
    return tensors, config


def lovasz_softmax(logits, labels):
    """Mean over the classes present of the Lovasz extension of the Jaccard loss at the errors."""
    keep = labels != IGNORE
    prob = F.softmax(logits[keep], dim=1)
    target = labels[keep]
    losses = []
    for c in range(prob.shape[1]):
        fg = (target == c).to(prob.dtype)
        if fg.sum() == 0:
            continue
        errors = (fg - prob[:, c]).abs()
        errors_sorted, order = torch.sort(errors, descending=True, stable=True)
        fg_sorted = fg[order]
        gts = fg_sorted.sum()
        jaccard = 1.0 - (gts - fg_sorted.cumsum(0)) / (gts + (1.0 - fg_sorted).cumsum(0))
        grad = torch.cat([jaccard[:1], jaccard[1:] - jaccard[:-1]])
        losses.append(torch.dot(errors_sorted, grad))
    return torch.stack(losses).mean()


def lovasz_margin(logits, labels):
    """Smallest gap between errors adjacent in a class's sorted order: a float32 trainer sorts
    them the same way when this is well above its logits' error."""
    keep = labels != IGNORE
    prob = F.softmax(logits.detach()[keep], dim=1)
    target = labels[keep]
    worst = np.inf
    for c in range(prob.shape[1]):
        e = np.sort((( target == c).to(prob.dtype) - prob[:, c]).abs().numpy())
        worst = min(worst, float(np.min(np.diff(e))))
    return worst


def train_forward(model, coord, feat, offsets, labels, trace=None, lovasz=False):
    with training_mode():
        logits = model(coord, feat, offsets=offsets, trace=trace)
    target = torch.from_numpy(labels.astype(np.int64))
    loss = F.cross_entropy(logits, target, ignore_index=IGNORE)
    if lovasz:
        loss = loss + lovasz_softmax(logits, target)
    return loss, logits


def check_batch_norm(tensors, model, x_by_bn):
    """torch's training BatchNorm, spelled out: the output uses the biased variance, the running
    statistics move by momentum 0.01 towards the mean and the unbiased variance.
    x_by_bn: BatchNorm name -> (its input, GELU of its output)."""
    worst = 0.0
    for name, (x, y) in x_by_bn.items():
        m = 0.01
        bn = model.get_submodule(name)
        mean = x.mean(0)
        with torch.no_grad():
            expect = F.gelu((x - mean) / torch.sqrt(x.var(0, unbiased=False) + bn.eps) * bn.weight + bn.bias)
        worst = max(worst, float((expect - y).abs().max()))
        var = x.var(0, unbiased=True)
        rm = (1 - m) * torch.from_numpy(tensors[name + ".running_mean"]).double() + m * mean
        rv = (1 - m) * torch.from_numpy(tensors[name + ".running_var"]).double() + m * var
        worst = max(worst, float((bn.running_mean - rm).abs().max()), float((bn.running_var - rv).abs().max()))
    if worst > 1e-12:
        raise RuntimeError("training BatchNorm differs from its definition by %.3e" % worst)
    return worst


# ----------------------------------------------------------------------------- input

def make_batch():
    """Two small clouds (box + sphere surface samples, one point per voxel) and labels."""
    # objects spread apart so that even level 4 (32 cm cells) keeps several points per cloud
    scene_a = [
        {"name": "crate", "kind": "box", "centre": [0.0, 0.0, 0.08], "size": [0.16, 0.14, 0.14], "yaw_deg": 25.0},
        {"name": "ball", "kind": "sphere", "centre": [0.32, 0.2, 0.07], "size": 0.06, "yaw_deg": 0.0},
        {"name": "can", "kind": "box", "centre": [-0.25, 0.3, 0.1], "size": [0.08, 0.08, 0.2], "yaw_deg": 10.0}]
    scene_b = [
        {"name": "post", "kind": "box", "centre": [0.06, 0.03, 0.1], "size": [0.07, 0.07, 0.2], "yaw_deg": -30.0},
        {"name": "pebble", "kind": "sphere", "centre": [0.4, -0.2, 0.05], "size": 0.05, "yaw_deg": 0.0},
        {"name": "slab", "kind": "box", "centre": [-0.2, -0.3, 0.03], "size": [0.2, 0.12, 0.05], "yaw_deg": 40.0}]
    coord, feat, info = fx.make_input(21, [scene_a, scene_b], [300, 200], [(0, 1), (1, 0)])

    rng = np.random.default_rng(22)
    labels = np.zeros(len(coord), dtype=np.int32)
    for cloud in info["clouds"]:
        a, n = cloud["first_point"], cloud["n"]
        d = np.linalg.norm(coord[a:a + n].astype(np.float64) - np.asarray(cloud["positive_click_xyz"]), axis=1)
        labels[a:a + n] = (d < LABEL_RADIUS).astype(np.int32)
    labels[rng.random(len(coord)) < IGNORE_FRACTION] = IGNORE
    info["labels"] = {
        "file": "labels.bin", "dtype": "int32", "shape": [len(coord)],
        "meaning": "1 within %g m of the cloud's positive click, 0 elsewhere, %d (ignored) on a random ~%d%%"
                   % (LABEL_RADIUS, IGNORE, round(IGNORE_FRACTION * 100)),
        "counts": {str(k): int(np.sum(labels == k)) for k in (IGNORE, 0, 1)}}
    return coord, feat, info, labels


def level_counts(trace, offsets_n):
    out = {}
    s = 0
    while ("enc.enc%d/batch" % s) in trace:
        b = trace["enc.enc%d/batch" % s]
        out["level%d" % s] = np.bincount(b, minlength=offsets_n).tolist()
        s += 1
    return out


def pooling_margins(model, trace):
    """Smallest gap between a cluster's max and runner-up per channel, relative to the max's
    magnitude (a float32 forward picks the same member when this is well above 1e-6); fails on
    exact ties, where autograd splits the gradient but an argmax routes it to one member."""
    worst = np.inf
    s = 1
    while ("enc.enc%d/pooling_inverse" % s) in trace:
        down = getattr(model.enc, "enc%d" % s).down
        with torch.no_grad():
            h = down.proj(torch.from_numpy(trace["enc.enc%d/feat" % (s - 1)])).numpy()
        cluster = trace["enc.enc%d/pooling_inverse" % s]
        order = np.lexsort((np.arange(len(cluster)), cluster))
        for c in range(h.shape[1]):
            col = h[order, c]
            cl = cluster[order]
            starts = np.flatnonzero(np.r_[True, cl[1:] != cl[:-1]])
            ends = np.r_[starts[1:], len(cl)]
            for a, e in zip(starts, ends):
                if e - a < 2:
                    continue
                v = np.sort(col[a:e])
                gap = (v[-1] - v[-2]) / max(abs(v[-1]), 1e-30)
                if gap == 0:
                    raise RuntimeError("enc%d: tie in the pooling max (cluster %d, channel %d)" % (s, cl[a], c))
                worst = min(worst, gap)
        s += 1
    return float(worst)


# ----------------------------------------------------------------------------- finite differences

def fd_entries(model, rng):
    """(name, flat index) pairs: a spread of tensors of every kind, each at its largest-|grad|
    entry and at a random entry whose |grad| is at least a tenth of that."""
    params = dict(model.named_parameters())
    must = ["embedding.stem.conv.weight", "embedding.stem.norm.weight", "embedding.stem.norm.bias",
            "enc.enc0.block0.cpe.0.weight", "enc.enc0.block0.attn.qkv.weight", "enc.enc1.down.proj.weight",
            "enc.enc2.down.norm.0.weight", "enc.enc4.block0.mlp.0.fc2.weight", "dec.dec3.up.proj.1.bias",
            "dec.dec0.up.proj_skip.1.weight", "dec.dec0.block1.cpe.2.weight", "dec.dec0.block0.norm1.0.bias",
            "cls_head.0.weight", "cls_head.0.bias"]
    # leave out gradients that are zero up to rounding (biases of Linears feeding a BatchNorm, ...)
    g_max = max(float(p.grad.abs().max()) for p in params.values())
    others = [k for k in params if k not in must and float(params[k].grad.abs().max()) > 1e-6 * g_max]
    names = must + [others[i] for i in sorted(rng.choice(len(others), size=6, replace=False))]
    out = []
    for name in names:
        g = params[name].grad.reshape(-1).abs().numpy()
        out.append((name, int(np.argmax(g))))
        big = np.flatnonzero(g >= 0.1 * g.max())
        out.append((name, int(big[rng.integers(len(big))])))
    return out


def fd_check(tensors, config, batch, grads, lovasz=False):
    coord, feat, offsets, labels = batch
    model = ref.load_model(tensors, config, torch.float64)
    probe = copy.deepcopy(model)
    for p in probe.parameters():
        p.requires_grad_(False)
    params = dict(probe.named_parameters())
    rng = np.random.default_rng(5)
    with_grad = ref.load_model(tensors, config, torch.float64)
    for name, p in with_grad.named_parameters():
        p.grad = torch.from_numpy(grads[name])
    rows = []
    worst = 0.0
    for name, i in fd_entries(with_grad, rng):
        flat = params[name].view(-1)
        v0 = float(flat[i])
        flat[i] = v0 + FD_STEP
        up, _ = train_forward(probe, coord, feat, offsets, labels, lovasz=lovasz)
        flat[i] = v0 - FD_STEP
        down, _ = train_forward(probe, coord, feat, offsets, labels, lovasz=lovasz)
        flat[i] = v0
        fd = (float(up) - float(down)) / (2 * FD_STEP)
        g = float(grads[name].reshape(-1)[i])
        rel = abs(fd - g) / max(abs(fd), abs(g), 1e-30)
        worst = max(worst, rel)
        rows.append({"name": name, "index": i, "autograd": g, "finite_difference": fd, "relative_error": rel})
    return worst, rows


# ----------------------------------------------------------------------------- main

def run_step(tensors, config, dtype, batch, trace=None, lovasz=False):
    coord, feat, offsets, labels = batch
    model = ref.load_model(tensors, config, dtype)
    loss, logits = train_forward(model, coord, feat, offsets, labels, trace=trace, lovasz=lovasz)
    loss.backward()
    grads = {}
    for name, p in model.named_parameters():
        if p.grad is None:
            raise RuntimeError("%s got no gradient" % name)
        grads[name] = p.grad.detach().numpy().copy()
    return model, loss, logits, grads


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else DEFAULT_OUT
    os.makedirs(out, exist_ok=True)
    torch.set_num_threads(1)  # one summation order on every machine we run on
    tensors, config = load_weights()
    coord, feat, info, labels = make_batch()
    offsets = info["offsets"]
    batch = (coord, feat, offsets, labels)

    trace = {}
    model, loss, logits, grads = run_step(tensors, config, torch.float64, batch, trace)
    trace = {k: v.numpy() if torch.is_tensor(v) else v for k, v in trace.items()}
    if trace["logits"].shape[0] != len(coord) or not np.array_equal(trace["enc.enc0/batch"],
                                                                     np.repeat([0, 1], np.diff([0] + offsets))):
        raise RuntimeError("the input has duplicate voxels")

    check_batch_norm(tensors, model, {"embedding.stem.norm": (torch.from_numpy(trace["embedding.stem.conv/feat"]),
                                                              torch.from_numpy(trace["embedding/feat"]))})
    margin = pooling_margins(model, trace)

    # float32 run of the same step: how far a float32 trainer may drift from the fixture
    _, loss32, logits32, grads32 = run_step(tensors, config, torch.float32, batch)
    g_max = max(np.abs(g).max() for g in grads.values())
    fp32_diff = {
        "loss_abs": abs(float(loss32) - float(loss)),
        "logits_max_abs": float((logits32.detach().double() - logits.detach()).abs().max()),
        # per tensor, relative to its largest entry (floored at 1e-3 of the largest of all: some
        # gradients are zero up to rounding, e.g. q/k of a window with one key)
        "grads_max_abs_over_tensor_max_abs": max(
            float(np.abs(grads32[k].astype(np.float64) - g).max() / max(np.abs(g).max(), 1e-3 * g_max))
            for k, g in grads.items())}

    fd_worst, fd_rows = fd_check(tensors, config, batch, grads)
    print("finite differences: %d entries, max relative error %.3e" % (len(fd_rows), fd_worst))
    if not fd_worst < FD_LIMIT:
        for r in fd_rows:
            print("  %-40s %6d  autograd %+.9e  fd %+.9e  rel %.2e" % (
                r["name"], r["index"], r["autograd"], r["finite_difference"], r["relative_error"]))
        raise RuntimeError("gradients disagree with finite differences (%.3e >= %g)" % (fd_worst, FD_LIMIT))

    # the same step with the Lovasz loss added
    _, loss_lv, _, grads_lv = run_step(tensors, config, torch.float64, batch, lovasz=True)
    lv_margin = lovasz_margin(logits, torch.from_numpy(labels.astype(np.int64)))
    fd_lv_worst, fd_lv_rows = fd_check(tensors, config, batch, grads_lv, lovasz=True)
    print("with Lovasz: loss %.9f, finite differences max relative error %.3e, sorted error min gap %.3e"
          % (float(loss_lv), fd_lv_worst, lv_margin))
    if not fd_lv_worst < FD_LIMIT:
        raise RuntimeError("Lovasz gradients disagree with finite differences (%.3e >= %g)" % (fd_lv_worst, FD_LIMIT))

    # files
    fx.write_input(out, "input", coord, feat, info)
    with open(os.path.join(out, "labels.bin"), "wb") as f:
        f.write(np.ascontiguousarray(labels, dtype="<i4").tobytes())
    result = {k: g.astype(np.float32) for k, g in grads.items()}
    result["loss"] = np.array([float(loss)], dtype=np.float32)
    result["logits"] = logits.detach().numpy().astype(np.float32)
    for name, b in model.named_buffers():
        if name.endswith(".running_mean") or name.endswith(".running_var"):
            result[name] = b.detach().numpy().astype(np.float32)
    with open(WEIGHTS, "rb") as f:
        weights_sha = hashlib.sha256(f.read()).hexdigest()
    meta = {"config": json.dumps(config), "format": "pointgauss-ptv3-train-grads",
            "weights": "../small/weights.safetensors", "weights_sha256": weights_sha,
            "input": "input.bin", "labels": "labels.bin",
            "loss": "mean softmax cross-entropy over points with label != -1",
            "batch_norm": "training: batch mean and biased variance; running stats after the step "
                          "with momentum 0.01 and the unbiased variance",
            "computed_in": "float64, stored as float32",
            "source": "tools/make_ptv3_train_fixture.py"}
    st.save(os.path.join(out, "grads.safetensors"), result, meta)
    result_lv = {k: g.astype(np.float32) for k, g in grads_lv.items()}
    result_lv["loss"] = np.array([float(loss_lv)], dtype=np.float32)
    meta_lv = dict(meta, loss="mean softmax cross-entropy + Lovasz-softmax (classes present) over points "
                              "with label != -1")
    st.save(os.path.join(out, "grads_lovasz.safetensors"), result_lv, meta_lv)

    n_params = sum(g.size for g in grads.values())
    summary = {
        "points_per_level": level_counts(trace, len(offsets)),
        "loss": float(loss), "labels": info["labels"]["counts"],
        "parameters": int(n_params), "parameter_tensors": len(grads),
        "batch_norm_layers": sum(1 for k in result if k.endswith(".running_mean")),
        "grad_max_abs": float(max(np.abs(g).max() for g in grads.values())),
        "pooling_min_relative_gap": margin,
        "fp32_vs_fp64": fp32_diff,
        "finite_differences": {"step": FD_STEP, "max_relative_error": fd_worst, "entries": fd_rows},
        "lovasz": {"loss": float(loss_lv), "sorted_error_min_gap": lv_margin,
                   "finite_differences": {"step": FD_STEP, "max_relative_error": fd_lv_worst,
                                          "entries": fd_lv_rows}}}
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")
    print("points per level: %s" % summary["points_per_level"])
    print("loss %.9f, labels %s, fp32 vs fp64: %s" % (float(loss), summary["labels"], fp32_diff))
    print("pooling min relative gap %.3e" % margin)


if __name__ == "__main__":
    main()
