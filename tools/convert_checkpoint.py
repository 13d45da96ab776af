#!/usr/bin/env python3
"""Converts a PyTorch PTv3 checkpoint into PointGauss's .safetensors model file.

    /usr/bin/python3 tools/convert_checkpoint.py IN.pth OUT.safetensors [--config paper|small|tiny|FILE.json]
        [--grid-size 0.02] [--patch-size 1024] [--head-dim 16]
    /usr/bin/python3 tools/convert_checkpoint.py --self-test

IN.pth may be a raw state_dict or a dict holding it under "state_dict" or "model". Tensor
names are written unchanged ("module." / "backbone." prefixes and "cls_head." / "seg_head."
heads included; the C++ loader accepts them). Floating tensors become F32, the BatchNorm
`num_batches_tracked` counters I64. __metadata__ = {"config": JSON, "format":
"pointgauss-ptv3", "source": IN's file name}.

Without --config the config is inferred from the tensor shapes: channels from the layers,
depths from the block counts, in_channels from the stem, classes from the head, heads =
channels / head dim (16), patch size 1024 and grid 0.02 m unless given. The config is
printed, and the checkpoint is checked against it (every tensor PTv3 needs must be present
with the right shape). Errors name the file and the reason and exit with status 1.
"""
import argparse
import json
import os
import re
import sys
import tempfile

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ptv3_reference as ref  # noqa: E402
import safetensors_io as st  # noqa: E402

STEM = "embedding.stem.conv.weight"
HEAD_RE = re.compile(r"^(?:.*\.)?(cls_head|seg_head)(\.0)?\.(weight|bias)$")


class ConvertError(Exception):
    pass


def load_checkpoint(path):
    """Returns the state_dict (name -> tensor) of a .pth file."""
    if not os.path.isfile(path):
        raise ConvertError("%s: no such file" % path)
    try:
        obj = torch.load(path, map_location="cpu", weights_only=True)
    except Exception:  # noqa: BLE001
        # training checkpoints may pickle scheduler objects; those need the full unpickler
        # (only convert checkpoints you trust)
        try:
            obj = torch.load(path, map_location="cpu")
        except Exception as e:  # noqa: BLE001 - any unpickling failure is a bad input file
            first = (str(e).splitlines() or [""])[0][:160]
            raise ConvertError("%s: not a readable PyTorch checkpoint (%s: %s)" % (path, type(e).__name__, first))
    if isinstance(obj, dict):
        for key in ("state_dict", "model"):
            if key in obj and isinstance(obj[key], dict):
                obj = obj[key]
                break
    if not isinstance(obj, dict) or not obj:
        raise ConvertError("%s: holds no state_dict (expected a dict of tensors, or one under "
                           "'state_dict' or 'model')" % path)
    tensors = {}
    for k, v in obj.items():
        if not isinstance(k, str) or not torch.is_tensor(v):
            raise ConvertError("%s: entry %r is not a named tensor" % (path, k))
        tensors[k] = v
    return tensors


def find_prefix(names, path):
    stems = [n for n in names if n.endswith(STEM)]
    if len(stems) != 1:
        raise ConvertError("%s: expected exactly one '*%s' tensor, found %d: not a PTv3 checkpoint"
                           % (path, STEM, len(stems)))
    return stems[0][:-len(STEM)]


def head_names(names):
    return {HEAD_RE.match(n).group(3): n for n in names if HEAD_RE.match(n)}


def infer_config(shapes, path, head_dim=16, patch=1024, grid=0.02):
    prefix = find_prefix(shapes, path)

    def shape(name):
        return shapes.get(prefix + name)

    stem = shape(STEM)
    if len(stem) != 5:
        raise ConvertError("%s: %s has shape %s, expected [out, 5, 5, 5, in]" % (path, prefix + STEM, list(stem)))
    in_channels = stem[4]
    enc_channels, enc_depths = [], []
    s = 0
    while shape("enc.enc%d.block0.attn.proj.weight" % s) is not None:
        enc_channels.append(shape("enc.enc%d.block0.attn.proj.weight" % s)[0])
        d = 0
        while shape("enc.enc%d.block%d.attn.proj.weight" % (s, d)) is not None:
            d += 1
        enc_depths.append(d)
        s += 1
    if not enc_channels:
        raise ConvertError("%s: no encoder blocks (enc.enc0.block0.*) found" % path)
    stages = len(enc_channels)
    dec_channels, dec_depths = [], []
    for s in range(stages - 1):
        up = shape("dec.dec%d.up.proj.0.weight" % s)
        if up is None:
            raise ConvertError("%s: missing %sdec.dec%d.up.proj.0.weight (a segmentation PTv3 has a "
                               "decoder stage per encoder level but the last)" % (path, prefix, s))
        dec_channels.append(up[0])
        d = 0
        while shape("dec.dec%d.block%d.attn.proj.weight" % (s, d)) is not None:
            d += 1
        dec_depths.append(d)
    heads = head_names(shapes)
    if "weight" not in heads:
        raise ConvertError("%s: no classification head (cls_head.0.weight or seg_head.weight)" % path)
    num_classes = shapes[heads["weight"]][0]
    fc1 = shape("enc.enc0.block0.mlp.0.fc1.weight")
    mlp_ratio = fc1[0] // enc_channels[0] if fc1 is not None else 4
    for c in enc_channels + dec_channels:
        if c % head_dim:
            raise ConvertError("%s: %d channels are not a multiple of head dim %d (give --head-dim or --config)"
                               % (path, c, head_dim))
    return ref.release_config(
        in_channels=in_channels, num_classes=num_classes, stride=[2] * (stages - 1),
        enc_depths=enc_depths, enc_channels=enc_channels,
        enc_num_head=[c // head_dim for c in enc_channels], enc_patch_size=[patch] * stages,
        dec_depths=dec_depths, dec_channels=dec_channels,
        dec_num_head=[c // head_dim for c in dec_channels], dec_patch_size=[patch] * (stages - 1),
        mlp_ratio=mlp_ratio, qkv_bias=shape("enc.enc0.block0.attn.qkv.bias") is not None, grid_size=grid)


def check_against(config, shapes, path):
    """Every tensor PTv3(config) has must be in the checkpoint (after its prefix) with its shape."""
    try:
        expected = {k: tuple(v.shape) for k, v in ref.PTv3(config).state_dict().items()}
    except (ValueError, KeyError, TypeError) as e:
        raise ConvertError("%s: invalid config (%s)" % (path, e))
    prefix = find_prefix(shapes, path)
    heads = head_names(shapes)
    problems, used = [], set()
    for name, want in expected.items():
        if name.startswith("cls_head."):
            leaf = name.rsplit(".", 1)[1]
            got_name = heads.get(leaf)
        else:
            got_name = prefix + name
        if got_name not in shapes:
            problems.append("missing %s" % (prefix + name))
            continue
        used.add(got_name)
        if tuple(shapes[got_name]) != want:
            problems.append("%s has shape %s, config needs %s" % (got_name, list(shapes[got_name]), list(want)))
    if problems:
        more = "" if len(problems) <= 8 else " (and %d more)" % (len(problems) - 8)
        raise ConvertError("%s: does not match the config: %s%s" % (path, "; ".join(problems[:8]), more))
    return sorted(set(shapes) - used)


def resolve_config(arg, path):
    if arg in ref.NAMED_CONFIGS:
        return ref.named_config(arg)
    if not os.path.isfile(arg):
        raise ConvertError("%s: --config is neither %s nor a readable file" % (arg, "|".join(ref.NAMED_CONFIGS)))
    try:
        with open(arg) as f:
            c = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        raise ConvertError("%s: cannot read the config JSON (%s)" % (arg, e))
    if isinstance(c, dict) and "config" in c and isinstance(c["config"], dict):
        c = c["config"]  # a manifest.json
    if not isinstance(c, dict):
        raise ConvertError("%s: config must be a JSON object" % arg)
    return ref.release_config(**c)


def convert(in_path, out_path, config_arg=None, grid=None, patch=None, head_dim=16, quiet=False):
    tensors = load_checkpoint(in_path)
    shapes = {k: tuple(v.shape) for k, v in tensors.items()}
    if config_arg:
        config = resolve_config(config_arg, in_path)
        if grid is not None:
            config["grid_size"] = grid
        if patch is not None:
            config["enc_patch_size"] = [patch] * len(config["enc_patch_size"])
            config["dec_patch_size"] = [patch] * len(config["dec_patch_size"])
    else:
        config = infer_config(shapes, in_path, head_dim, patch or 1024, grid if grid is not None else 0.02)
    unused = check_against(config, shapes, in_path)
    out = {}
    for k, v in tensors.items():
        if k.endswith("num_batches_tracked"):
            out[k] = v.detach().to(torch.int64).reshape(v.shape).numpy()
        elif v.is_floating_point():
            out[k] = v.detach().to(torch.float32).numpy()
        else:
            raise ConvertError("%s: tensor %s has dtype %s, expected floating point" % (in_path, k, v.dtype))
    meta = {"config": json.dumps(config), "format": "pointgauss-ptv3", "source": os.path.basename(in_path)}
    tmp = out_path + ".tmp"
    try:
        st.save(tmp, out, meta)
        os.replace(tmp, out_path)
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise ConvertError("%s: cannot write (%s)" % (out_path, e.strerror or e))
    if not quiet:
        print(json.dumps(config, indent=1))
        if unused:
            print("note: %d tensors not used by PTv3 kept as they are: %s" % (len(unused), ", ".join(unused[:6])),
                  file=sys.stderr)
        print("wrote %s: %d tensors, %d parameters" % (
            out_path, len(out), sum(int(np.prod(s)) for k, s in shapes.items() if "running" not in k
                                    and not k.endswith("num_batches_tracked"))))
    return config


def self_test():
    """Round trips a reference model's state_dict through .pth variants."""
    config = ref.named_config("tiny")
    model = ref.PTv3(config)
    g = torch.Generator().manual_seed(0)
    sd = {k: (torch.rand(v.shape, generator=g) if v.is_floating_point() else v) for k, v in model.state_dict().items()}
    seg = {("backbone." + k if not k.startswith("cls_head.") else k.replace("cls_head.0.", "seg_head.")): v
           for k, v in sd.items()}
    variants = {
        "plain": sd,
        "module": {"module." + k: v for k, v in sd.items()},
        "state_dict": {"state_dict": sd, "epoch": 3},
        "model_seg": {"model": {"module." + k: v for k, v in seg.items()}},
    }
    failures = 0
    with tempfile.TemporaryDirectory() as d:
        for name, obj in variants.items():
            pth = os.path.join(d, name + ".pth")
            out = os.path.join(d, name + ".safetensors")
            torch.save(obj, pth)
            inferred = convert(pth, out, quiet=True, head_dim=8, patch=48)
            loaded, meta = st.load(out)
            src = obj.get("state_dict") or obj.get("model") or obj
            same = list(loaded) == list(src) and all(
                np.array_equal(loaded[k], src[k].numpy()) and loaded[k].dtype == (
                    np.int64 if k.endswith("num_batches_tracked") else np.float32) for k in src)
            cfg_ok = json.loads(meta["config"]) == config == inferred
            ok = same and cfg_ok and meta["format"] == "pointgauss-ptv3" and meta["source"] == name + ".pth"
            failures += not ok
            print("%-12s tensors %s, config %s" % (name, "equal" if same else "DIFFER", "equal" if cfg_ok else "DIFFERS"))
        # the converted plain file loads into the reference strictly
        loaded, meta = st.load(os.path.join(d, "plain.safetensors"))
        ref.load_model(loaded, json.loads(meta["config"]))
        # bad inputs: each must raise ConvertError naming the file
        bad_txt = os.path.join(d, "bad.pth")
        with open(bad_txt, "w") as f:
            f.write("not a checkpoint")
        cut = dict(sd)
        cut.pop("enc.enc1.block0.attn.qkv.weight")
        torch.save(cut, os.path.join(d, "cut.pth"))
        torch.save({"epoch": 1}, os.path.join(d, "nodict.pth"))
        for case, args in [("missing file", (os.path.join(d, "nope.pth"), None)),
                           ("garbage", (bad_txt, None)),
                           ("missing tensor", (os.path.join(d, "cut.pth"), "tiny")),
                           ("no tensors", (os.path.join(d, "nodict.pth"), None)),
                           ("wrong config", (os.path.join(d, "plain.pth"), "paper"))]:
            try:
                convert(args[0], os.path.join(d, "x.safetensors"), args[1], quiet=True, head_dim=8)
                print("%-14s NOT REJECTED" % case)
                failures += 1
            except ConvertError as e:
                named = os.path.basename(args[0]) in str(e)
                failures += not named
                print("%-14s rejected: %s" % (case, str(e)[:150].replace(d + "/", "")))
            if os.path.exists(os.path.join(d, "x.safetensors")):
                print("%-14s LEFT AN OUTPUT FILE" % case)
                failures += 1
    print("self-test %s" % ("PASS" if failures == 0 else "FAIL (%d)" % failures))
    return 0 if failures == 0 else 1


def main():
    ap = argparse.ArgumentParser(description="Convert a PyTorch PTv3 checkpoint to PointGauss .safetensors")
    ap.add_argument("input", nargs="?", help="checkpoint (.pth)")
    ap.add_argument("output", nargs="?", help="output .safetensors")
    ap.add_argument("--config", help="paper | small | tiny | FILE.json (default: infer from shapes)")
    ap.add_argument("--grid-size", type=float, help="voxel size in metres (default 0.02)")
    ap.add_argument("--patch-size", type=int, help="attention window (default 1024 when inferred)")
    ap.add_argument("--head-dim", type=int, default=16, help="channels per head when inferring (default 16)")
    ap.add_argument("--self-test", action="store_true", help="round-trip test on a generated model")
    args = ap.parse_args()
    torch.set_num_threads(min(2, torch.get_num_threads()))
    if args.self_test:
        return self_test()
    if not args.input or not args.output:
        ap.error("IN.pth and OUT.safetensors are required")
    try:
        convert(args.input, args.output, args.config, args.grid_size, args.patch_size, args.head_dim)
    except ConvertError as e:
        print("convert_checkpoint: %s" % e, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
