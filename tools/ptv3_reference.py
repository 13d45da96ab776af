#!/usr/bin/env python3
"""An independent Point Transformer V3 in plain PyTorch (no spconv, torch_scatter or flash-attn).

It loads the release's checkpoints unchanged: `PTv3(config).state_dict()` has exactly the
names, shapes and order of the official model (plus `cls_head.0`), so
`load_state_dict(..., strict=True)` works. It runs in float32 or float64 (`model.double()`).
The semantics follow /work/shared/reference/ptv3-semantics.md:

- grid = trunc((coord - coord.min over the whole batch) / grid_size), computed in float32;
  depth = bit_length(max grid entry over the batch); code = batch << 3d | curve(grid).
- Several points in one voxel: one point per voxel (the lowest input index) goes through the
  network and every point gets the logits of its voxel's point (Pointcept's test-time
  GridSample with an inverse map). The grid is computed before sampling, from all points.
- Attention windows follow the flash-attention path of the release: position p of a cloud's
  serialized order attends to the K positions starting at min(floor(p/K)*K, n-K); a cloud
  with n <= K attends to itself whole; never across clouds.
- `perms` optionally gives, per level, the permutation of the order list that the release
  draws at random (level 0 at the input, level s at the pooling into s); None = fixed order.

Usage as a module:
    model = PTv3(config); model.load_state_dict(tensors); model.eval()
    logits = model(coord, feat, offsets=[n0, n0 + n1])
    logits, trace = run_with_trace(model, coord, feat, offsets)
"""
import json
import math
import warnings

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

DEFAULT_ORDER = ["z", "z-trans", "hilbert", "hilbert-trans"]

CONFIG_KEYS = ["in_channels", "num_classes", "order", "stride", "enc_depths", "enc_channels",
               "enc_num_head", "enc_patch_size", "dec_depths", "dec_channels", "dec_num_head",
               "dec_patch_size", "mlp_ratio", "qkv_bias", "qk_scale", "grid_size"]

# keys and fixed values of the release's constructor (as in the shared manifest's config),
# plus grid_size; the sizes are filled per named config
RELEASE_CONFIG = {
    "in_channels": 2, "order": DEFAULT_ORDER, "stride": [2, 2, 2, 2],
    "enc_depths": None, "enc_channels": None, "enc_num_head": None, "enc_patch_size": None,
    "dec_depths": None, "dec_channels": None, "dec_num_head": None, "dec_patch_size": None,
    "mlp_ratio": 4, "qkv_bias": True, "qk_scale": None, "attn_drop": 0.0, "proj_drop": 0.0,
    "drop_path": 0.3, "pre_norm": True, "shuffle_orders": False, "enable_rpe": False,
    "enable_flash": False, "upcast_attention": False, "upcast_softmax": False, "cls_mode": False,
    "pdnorm_bn": False, "pdnorm_ln": False, "pdnorm_decouple": True, "pdnorm_adaptive": False,
    "pdnorm_affine": True, "pdnorm_conditions": ["ScanNet", "S3DIS", "Structured3D"],
    "num_classes": 2, "grid_size": 0.02,
}


def release_config(**sizes):
    c = json.loads(json.dumps(RELEASE_CONFIG))
    c.update(sizes)
    return c


NAMED_CONFIGS = {
    # the paper's model (46,150,402 parameters)
    "paper": dict(enc_depths=[2, 2, 2, 6, 2], enc_channels=[32, 64, 128, 256, 512],
                  enc_num_head=[2, 4, 8, 16, 32], enc_patch_size=[1024] * 5, dec_depths=[2, 2, 2, 2],
                  dec_channels=[64, 64, 128, 256], dec_num_head=[4, 4, 8, 16], dec_patch_size=[1024] * 4),
    # /work/shared/fixtures/ptv3-small (5,179,922 parameters)
    "small": dict(enc_depths=[1, 1, 1, 2, 1], enc_channels=[16, 32, 64, 128, 256],
                  enc_num_head=[1, 2, 4, 8, 16], enc_patch_size=[128] * 5, dec_depths=[1, 1, 1, 1],
                  dec_channels=[32, 32, 64, 128], dec_num_head=[2, 2, 4, 8], dec_patch_size=[128] * 4),
    # tests/fixtures/ptv3/small (240,234 parameters, head dim 8)
    "tiny": dict(enc_depths=[1, 1, 1, 2, 1], enc_channels=[8, 16, 16, 32, 32],
                 enc_num_head=[1, 2, 2, 4, 4], enc_patch_size=[48] * 5, dec_depths=[2, 1, 1, 1],
                 dec_channels=[16, 16, 16, 32], dec_num_head=[2, 2, 2, 4], dec_patch_size=[48] * 4),
}


def named_config(name):
    if name not in NAMED_CONFIGS:
        raise ValueError("unknown config %r (known: %s)" % (name, ", ".join(NAMED_CONFIGS)))
    return release_config(**NAMED_CONFIGS[name])


PAPER_CONFIG = named_config("paper")


def normalize_config(config):
    """Fills defaults and checks the lengths; returns a new dict with CONFIG_KEYS."""
    c = dict(PAPER_CONFIG)
    c.update({k: v for k, v in config.items() if k in CONFIG_KEYS})
    s = len(c["enc_channels"])
    for k in ["enc_depths", "enc_num_head", "enc_patch_size"]:
        if len(c[k]) != s:
            raise ValueError("config: %s has %d entries, expected %d" % (k, len(c[k]), s))
    for k in ["stride", "dec_depths", "dec_channels", "dec_num_head", "dec_patch_size"]:
        if len(c[k]) != s - 1:
            raise ValueError("config: %s has %d entries, expected %d" % (k, len(c[k]), s - 1))
    if any(st != 2 for st in c["stride"]):
        raise ValueError("config: only stride 2 is supported")
    for ch, h in list(zip(c["enc_channels"], c["enc_num_head"])) + list(zip(c["dec_channels"], c["dec_num_head"])):
        if ch % h:
            raise ValueError("config: %d channels not divisible by %d heads" % (ch, h))
    return c


# ----------------------------------------------------------------------------- serialization

def bit_length(v):
    return int(v).bit_length()


def z_order(x, y, z, depth):
    """Interleaves bit i of x, y, z to bits 3i+2, 3i+1, 3i (int64 numpy arrays)."""
    code = np.zeros_like(x)
    for i in range(depth):
        code |= ((x >> i) & 1) << (3 * i + 2)
        code |= ((y >> i) & 1) << (3 * i + 1)
        code |= ((z >> i) & 1) << (3 * i)
    return code


def hilbert(x, y, z, depth):
    """Skilling's axes-to-transpose, MSB-first interleave, then Gray-to-binary (release variant)."""
    axes = [x.copy(), y.copy(), z.copy()]
    for q in range(depth - 1, 0, -1):
        bit = np.int64(1) << q
        low = bit - 1
        for i in range(3):
            on = (axes[i] & bit) != 0
            # bit set: invert the low bits of axis 0; bit clear: exchange low bits of axes 0 and i
            t = np.where(on, 0, (axes[0] ^ axes[i]) & low)
            axes[0] = np.where(on, axes[0] ^ low, axes[0] ^ t)
            axes[i] = axes[i] ^ t
    h = np.zeros_like(x)
    for q in range(depth):
        for i in range(3):
            h |= ((axes[i] >> q) & 1) << (3 * q + 2 - i)
    shift = 1
    while shift < 64:
        h ^= h >> shift
        shift <<= 1
    return h


def encode(grid, batch, depth, order):
    g = grid.astype(np.int64)
    x, y, z = g[:, 0], g[:, 1], g[:, 2]
    if order.endswith("-trans"):
        x, y = y, x
    if order.startswith("z"):
        code = z_order(x, y, z, depth)
    elif order.startswith("hilbert"):
        code = hilbert(x, y, z, depth)
    else:
        raise ValueError("unknown order %s" % order)
    return (batch.astype(np.int64) << (3 * depth)) | code


def argsort_with_inverse(code):
    """code [k, n] -> order, inverse (both [k, n] int64)."""
    order = np.argsort(code, axis=1, kind="stable")
    inverse = np.empty_like(order)
    rows = np.arange(code.shape[0])[:, None]
    inverse[rows, order] = np.arange(code.shape[1])[None, :]
    return order, inverse


def grid_coordinates(coord32, grid_size):
    """trunc((coord - min over batch) / grid_size) in float32, as the release computes it."""
    c = np.asarray(coord32, dtype=np.float32)
    rel = (c - c.min(axis=0)).astype(np.float32)
    return np.trunc(rel / np.float32(grid_size)).astype(np.int32)


# ----------------------------------------------------------------------------- sparse conv

class NeighbourTable:
    """Index of the voxel at p + offset for every point and kernel offset (-1 if empty)."""

    def __init__(self, grid, batch, kernel):
        r = kernel // 2
        g = grid.astype(np.int64) + r
        m = int(g.max()) + r + 1 if len(g) else 1
        self.m = m

        def key(b, gg):
            return ((b * m + gg[:, 0]) * m + gg[:, 1]) * m + gg[:, 2]

        b = batch.astype(np.int64)
        keys = key(b, g)
        sort = np.argsort(keys, kind="stable")
        sorted_keys = keys[sort]
        table = np.full((len(g), kernel ** 3), -1, dtype=np.int64)
        t = 0
        for rx in range(kernel):
            for ry in range(kernel):
                for rz in range(kernel):
                    q = g + np.array([rx - r, ry - r, rz - r], dtype=np.int64)
                    k = key(b, q)
                    pos = np.searchsorted(sorted_keys, k)
                    pos = np.minimum(pos, len(g) - 1)
                    hit = sorted_keys[pos] == k
                    table[:, t] = np.where(hit, sort[pos], -1)
                    t += 1
        self.table = table


class SubMConv3d(nn.Module):
    """Submanifold conv, weight [out, kx, ky, kz, in] (spconv 2.x), cross-correlation:
    out[p] = sum_t W[:, t, :] @ x[voxel at p + (rx-K/2, ry-K/2, rz-K/2)], t = (rx*K+ry)*K+rz."""

    def __init__(self, cin, cout, kernel, bias):
        super().__init__()
        self.kernel = kernel
        self.weight = nn.Parameter(torch.zeros(cout, kernel, kernel, kernel, cin))
        if bias:
            self.bias = nn.Parameter(torch.zeros(cout))
        else:
            self.register_parameter("bias", None)

    def forward(self, x, table):
        cout = self.weight.shape[0]
        w = self.weight.reshape(cout, self.kernel ** 3, -1)
        out = x.new_zeros(x.shape[0], cout)
        nbr = torch.from_numpy(table)
        for t in range(self.kernel ** 3):
            idx = nbr[:, t]
            valid = idx >= 0
            if not bool(valid.any()):
                continue
            rows = torch.nonzero(valid).squeeze(1)
            out.index_add_(0, rows, x[idx[valid]] @ w[:, t, :].t())
        if self.bias is not None:
            out = out + self.bias
        return out


# ----------------------------------------------------------------------------- modules

def batch_norm(bn, x):
    return F.batch_norm(x, bn.running_mean.to(x.dtype), bn.running_var.to(x.dtype),
                        bn.weight, bn.bias, False, 0.0, bn.eps)


def make_bn(c):
    return nn.BatchNorm1d(c, eps=1e-3, momentum=0.01)


class Attention(nn.Module):
    def __init__(self, channels, heads, patch, qkv_bias, qk_scale):
        super().__init__()
        self.channels, self.heads, self.patch = channels, heads, patch
        self.scale = qk_scale or (channels // heads) ** -0.5
        self.qkv = nn.Linear(channels, 3 * channels, bias=qkv_bias)
        self.proj = nn.Linear(channels, channels)

    def forward(self, x, order, segments):
        """order: serialized order [n]; segments: list of (start, end) of clouds within it."""
        C, H = self.channels, self.heads
        D = C // H
        qkv = self.qkv(x)[torch.from_numpy(order)]
        out = torch.empty(x.shape[0], C, dtype=x.dtype)
        for a, b in segments:
            n = b - a
            K = min(self.patch, n)
            nw = (n + K - 1) // K
            starts = np.minimum(np.arange(nw) * K, n - K)
            keys = torch.from_numpy(a + starts[:, None] + np.arange(K)[None, :])  # [nw, K]
            kv = qkv[keys].reshape(nw, K, 3, H, D)
            q, k, v = kv[:, :, 0].transpose(1, 2), kv[:, :, 1].transpose(1, 2), kv[:, :, 2].transpose(1, 2)
            att = torch.softmax((q * self.scale) @ k.transpose(-2, -1), dim=-1)
            o = (att @ v).transpose(1, 2).reshape(nw, K, C)  # rows = key positions of each window
            # window w answers the queries [w*K, min((w+1)*K, n)); the last window is shifted
            for w in range(nw):
                q0, q1 = w * K, min((w + 1) * K, n)
                out[a + q0:a + q1] = o[w, q0 - int(starts[w]):q1 - int(starts[w])]
        feat = torch.empty_like(out)
        feat[torch.from_numpy(order)] = out
        return self.proj(feat)


class MLP(nn.Module):
    def __init__(self, c, hidden):
        super().__init__()
        self.fc1 = nn.Linear(c, hidden)
        self.fc2 = nn.Linear(hidden, c)

    def forward(self, x):
        return self.fc2(F.gelu(self.fc1(x)))


class Block(nn.Module):
    def __init__(self, c, heads, patch, mlp_ratio, qkv_bias, qk_scale, order_index):
        super().__init__()
        self.order_index = order_index
        self.cpe = nn.Sequential(SubMConv3d(c, c, 3, True), nn.Linear(c, c), nn.LayerNorm(c))
        self.norm1 = nn.Sequential(nn.LayerNorm(c))
        self.attn = Attention(c, heads, patch, qkv_bias, qk_scale)
        self.norm2 = nn.Sequential(nn.LayerNorm(c))
        self.mlp = nn.Sequential(MLP(c, int(c * mlp_ratio)))

    def forward(self, feat, conv_in, level, rec, name):
        """conv_in: what the CPE conv reads (differs from feat after an unpooling)."""
        rec(name + ".cpe.0/input", conv_in)
        h = self.cpe[0](conv_in, level.table3)
        rec(name + ".cpe.0/feat", h)
        h = self.cpe[1](h)
        rec(name + ".cpe.1/feat", h)
        h = self.cpe[2](h)
        rec(name + ".cpe.2/feat", h)
        rec(name + ".cpe/feat", h)
        x = feat + h
        h = self.norm1(x)
        rec(name + ".norm1/feat", h)
        h = self.attn(h, level.order[self.order_index], level.segments[self.order_index])
        rec(name + ".attn/feat", h)
        x = x + h
        h = self.norm2(x)
        rec(name + ".norm2/feat", h)
        h = self.mlp(h)
        rec(name + ".mlp/feat", h)
        x = x + h
        rec(name + "/feat", x)
        return x


class Pooling(nn.Module):
    def __init__(self, cin, cout):
        super().__init__()
        self.proj = nn.Linear(cin, cout)
        self.norm = nn.Sequential(make_bn(cout))


class Unpooling(nn.Module):
    def __init__(self, cin, cskip, cout):
        super().__init__()
        self.proj = nn.Sequential(nn.Linear(cin, cout), make_bn(cout))
        self.proj_skip = nn.Sequential(nn.Linear(cskip, cout), make_bn(cout))


class Stem(nn.Module):
    def __init__(self, cin, cout):
        super().__init__()
        self.conv = SubMConv3d(cin, cout, 5, False)
        self.norm = make_bn(cout)


class Embedding(nn.Module):
    def __init__(self, cin, cout):
        super().__init__()
        self.stem = Stem(cin, cout)


class Container(nn.Module):
    """A named bag of submodules (gives the release's `enc.enc0.block0...` names)."""


# ----------------------------------------------------------------------------- levels

class Level:
    """What one resolution level carries: voxels, codes, orders, clouds, conv neighbours."""

    def __init__(self, grid, batch, coord, code, depth, n_orders, pooling_inverse=None):
        self.grid, self.batch, self.coord, self.depth = grid, batch, coord, depth
        self.code = code
        self.order, self.inverse = argsort_with_inverse(code)
        self.pooling_inverse = pooling_inverse
        counts = np.bincount(batch, minlength=int(batch.max()) + 1 if len(batch) else 0)
        ends = np.cumsum(counts)
        # codes carry the batch in their high bits, so every order lists the clouds in turn
        self.segments = [[(int(e - c), int(e)) for c, e in zip(counts, ends) if c > 0]] * n_orders
        self._table3 = None
        self._table5 = None

    @property
    def table3(self):
        if self._table3 is None:
            self._table3 = NeighbourTable(self.grid, self.batch, 3).table
        return self._table3

    @property
    def table5(self):
        if self._table5 is None:
            self._table5 = NeighbourTable(self.grid, self.batch, 5).table
        return self._table5

    def pad_unpad(self, patch):
        """The release's padded layout (traced for comparison only)."""
        counts = np.array([b - a for a, b in self.segments[0]], dtype=np.int64)
        padded = np.where(counts > patch, (counts + patch - 1) // patch * patch, counts)
        off = np.concatenate([[0], np.cumsum(counts)])
        off_pad = np.concatenate([[0], np.cumsum(padded)])
        pad = np.arange(off_pad[-1], dtype=np.int64)
        unpad = np.arange(off[-1], dtype=np.int64)
        for i in range(len(counts)):
            unpad[off[i]:off[i + 1]] += off_pad[i] - off[i]
            if counts[i] != padded[i]:
                r = counts[i] % patch
                pad[off_pad[i + 1] - patch + r:off_pad[i + 1]] = \
                    pad[off_pad[i + 1] - 2 * patch + r:off_pad[i + 1] - patch]
            pad[off_pad[i]:off_pad[i + 1]] -= off_pad[i] - off[i]
        return pad, unpad

    def pooled(self, perm):
        """Stride-2 serialized pooling: clusters = unique(code[0] >> 3)."""
        shift = 1 if self.depth >= 1 else 0
        code = self.code >> (3 * shift)
        uniq, cluster = np.unique(code[0], return_inverse=True)
        head = np.full(len(uniq), -1, dtype=np.int64)
        # any member works for the head (they share the coarse voxel); take the first
        head[cluster[::-1]] = np.arange(len(cluster))[::-1]
        coarse_code = code[:, head]
        if perm is not None:
            coarse_code = coarse_code[list(perm)]
        counts = np.bincount(cluster, minlength=len(uniq)).astype(np.float32)
        coord = np.zeros((len(uniq), 3), dtype=np.float32)
        np.add.at(coord, cluster, self.coord.astype(np.float32))
        coord = (coord / counts[:, None]).astype(np.float32)
        return Level(self.grid[head] >> shift, self.batch[head], coord, coarse_code,
                     self.depth - shift, code.shape[0], pooling_inverse=cluster)


# ----------------------------------------------------------------------------- model

class PTv3(nn.Module):
    def __init__(self, config):
        super().__init__()
        c = normalize_config(config)
        self.config = c
        S = len(c["enc_channels"])
        self.embedding = Embedding(c["in_channels"], c["enc_channels"][0])
        self.enc = Container()
        n_orders = len(c["order"])
        for s in range(S):
            stage = Container()
            if s > 0:
                stage.add_module("down", Pooling(c["enc_channels"][s - 1], c["enc_channels"][s]))
            for i in range(c["enc_depths"][s]):
                stage.add_module("block%d" % i, Block(
                    c["enc_channels"][s], c["enc_num_head"][s], c["enc_patch_size"][s],
                    c["mlp_ratio"], c["qkv_bias"], c["qk_scale"], i % n_orders))
            self.enc.add_module("enc%d" % s, stage)
        self.dec = Container()
        dec_channels = list(c["dec_channels"]) + [c["enc_channels"][-1]]
        for s in reversed(range(S - 1)):
            stage = Container()
            stage.add_module("up", Unpooling(dec_channels[s + 1], c["enc_channels"][s], dec_channels[s]))
            for i in range(c["dec_depths"][s]):
                stage.add_module("block%d" % i, Block(
                    dec_channels[s], c["dec_num_head"][s], c["dec_patch_size"][s],
                    c["mlp_ratio"], c["qkv_bias"], c["qk_scale"], i % n_orders))
            self.dec.add_module("dec%d" % s, stage)
        self.cls_head = nn.Sequential(nn.Linear(dec_channels[0], c["num_classes"]))

    @property
    def dtype(self):
        return self.cls_head[0].weight.dtype

    def forward(self, coord, feat, offsets=None, batch=None, perms=None, trace=None):
        """coord [N,3], feat [N,C] (tensors or arrays); offsets = cumulative cloud ends (or
        batch = cloud id per point, sorted); perms = per level a permutation of the orders;
        trace = dict to fill with intermediate tensors. Returns logits [N, classes]."""
        c = self.config
        dtype = self.dtype
        coord32 = np.asarray(torch.as_tensor(coord).detach().cpu().numpy(), dtype=np.float32)
        feat_t = torch.as_tensor(np.asarray(torch.as_tensor(feat).detach().cpu().numpy())).to(dtype)
        n = coord32.shape[0]
        if coord32.ndim != 2 or coord32.shape[1] != 3:
            raise ValueError("coord must be [N,3], got %s" % (coord32.shape,))
        if feat_t.shape != (n, c["in_channels"]):
            raise ValueError("feat must be [%d,%d], got %s" % (n, c["in_channels"], tuple(feat_t.shape)))
        if batch is None:
            if offsets is None:
                offsets = [n]
            offsets = np.asarray(offsets, dtype=np.int64)
            if len(offsets) == 0 or offsets[-1] != n or np.any(np.diff(np.concatenate([[0], offsets])) < 0):
                raise ValueError("offsets must be non-decreasing cumulative ends reaching N")
            batch = np.repeat(np.arange(len(offsets)), np.diff(np.concatenate([[0], offsets])))
        batch = np.asarray(batch, dtype=np.int64)
        if np.any(np.diff(batch) < 0):
            raise ValueError("batch ids must be sorted")

        def rec(name, value):
            if trace is not None:
                trace[name] = value.detach().clone() if torch.is_tensor(value) else np.array(value)

        rec("input/coord", torch.from_numpy(coord32))
        rec("input/feat", feat_t)

        grid = grid_coordinates(coord32, c["grid_size"])
        # one point per (cloud, voxel), the lowest index, in input order
        vkey = np.stack([batch, grid[:, 0], grid[:, 1], grid[:, 2]], axis=1)
        _, first, voxel_of_point = np.unique(vkey, axis=0, return_index=True, return_inverse=True)
        keep = np.sort(first)
        remap = np.empty(len(first), dtype=np.int64)
        remap[np.argsort(first)] = np.arange(len(first))  # unique row -> position in keep
        point_to_kept = remap[voxel_of_point.reshape(-1)]
        grid, batch_k, coord_k = grid[keep], batch[keep], coord32[keep]
        x = feat_t[torch.from_numpy(keep)]

        depth = bit_length(grid.max()) if len(grid) else 0
        code = np.stack([encode(grid, batch_k, depth, o) for o in c["order"]])
        if perms is not None and perms[0] is not None:
            code = code[list(perms[0])]
        level = Level(grid, batch_k, coord_k, code, depth, len(c["order"]))

        rec("embedding.stem.conv/input", x)
        stem = self.embedding.stem
        x = stem.conv(x, level.table5)
        rec("embedding.stem.conv/feat", x)
        x = F.gelu(batch_norm(stem.norm, x))
        rec("embedding/feat", x)

        S = len(c["enc_channels"])
        levels, skips = [], []
        for s in range(S):
            stage = getattr(self.enc, "enc%d" % s)
            name = "enc.enc%d" % s
            if s > 0:
                perm = perms[s] if perms is not None and len(perms) > s else None
                level = level.pooled(perm)
                down = stage.down
                h = down.proj(x)
                idx = torch.from_numpy(level.pooling_inverse)
                pooled = torch.full((len(level.grid), h.shape[1]), -math.inf, dtype=h.dtype)
                with warnings.catch_warnings():  # scatter_reduce is "beta" in torch 1.13
                    warnings.simplefilter("ignore")
                    pooled = pooled.scatter_reduce(0, idx[:, None].expand_as(h), h, reduce="amax")
                x = F.gelu(batch_norm(down.norm[0], pooled))
                rec(name + ".down/feat", x)
            for i in range(c["enc_depths"][s]):
                x = getattr(stage, "block%d" % i)(x, x, level, rec, "%s.block%d" % (name, i))
            rec(name + "/feat", x)
            self._record_level(rec, name, level, c["enc_patch_size"][s])
            levels.append(level)
            skips.append(x)

        for s in reversed(range(S - 1)):
            stage = getattr(self.dec, "dec%d" % s)
            name = "dec.dec%d" % s
            fine, coarse = levels[s], levels[s + 1]
            up = stage.up
            h = F.gelu(batch_norm(up.proj[1], up.proj[0](x)))
            skip = F.gelu(batch_norm(up.proj_skip[1], up.proj_skip[0](skips[s])))
            x = skip + h[torch.from_numpy(coarse.pooling_inverse)]
            rec(name + ".up/feat", x)
            conv_in = skip  # release quirk: the first block's CPE reads the skip projection alone
            for i in range(c["dec_depths"][s]):
                x = getattr(stage, "block%d" % i)(x, conv_in, fine, rec, "%s.block%d" % (name, i))
                conv_in = x
            rec(name + "/feat", x)

        logits = self.cls_head(x)
        logits = logits[torch.from_numpy(point_to_kept)]
        rec("logits", logits)
        return logits

    @staticmethod
    def _record_level(rec, name, level, patch):
        rec(name + "/grid_coord", level.grid.astype(np.int32))
        rec(name + "/coord", level.coord.astype(np.float32))
        rec(name + "/batch", level.batch.astype(np.int64))
        rec(name + "/serialized_code", level.code)
        rec(name + "/serialized_order", level.order)
        rec(name + "/serialized_inverse", level.inverse)
        if level.pooling_inverse is not None:
            rec(name + "/pooling_inverse", level.pooling_inverse.astype(np.int64))
        pad, unpad = level.pad_unpad(patch)
        rec(name + "/pad", pad)
        rec(name + "/unpad", unpad)


def run_with_trace(model, coord, feat, offsets=None, batch=None, perms=None):
    """Returns (logits, trace) with trace: name -> numpy array (floats in the model's dtype)."""
    trace = {}
    with torch.no_grad():
        logits = model(coord, feat, offsets=offsets, batch=batch, perms=perms, trace=trace)
    out = {}
    for k, v in trace.items():
        out[k] = v.numpy() if torch.is_tensor(v) else v
    return logits, out


def load_model(tensors, config, dtype=torch.float32):
    """Builds a PTv3 from numpy tensors (name -> array) with strict name checking."""
    model = PTv3(config)
    state = {k: torch.from_numpy(np.array(v)) for k, v in tensors.items()}
    model.load_state_dict(state, strict=True)
    model.eval()
    return model.to(dtype)


def count_parameters(model):
    return sum(p.numel() for p in model.parameters())
