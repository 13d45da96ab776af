#!/usr/bin/env python3
"""How a decoder's answer depends on where the first clicks land: N random prompts for one scene
of a benchmark suite, each object clicked once at a random pixel at least 3 px inside its mask in
a random view, every prompt segmented and scored in 3D (segment --views none, eval).

usage: tools/click_sweep.py SUITE SCENE N SEED OUT [segment options...]
  e.g. tools/click_sweep.py /tmp/gsuite guitar 48 40 /tmp/sweep --up -y
Prints per prompt the objects' 3D IoU, then mean / median / minimum per object. Needs numpy,
PIL and a build in build/ (or PG=path/to/pointgauss)."""
import json, os, random, statistics, subprocess, sys

import numpy as np
from PIL import Image

suite, scene, n, seed, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
extra = sys.argv[6:]
pg = os.environ.get("PG", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "app", "pointgauss"))
scene_dir = os.path.join(suite, scene)
meta = json.load(open(os.path.join(scene_dir, "meta.json")))
objects = [(o["id"], o.get("name", str(o["id"]))) for o in meta["instances"]]
mask_dir = os.path.join(scene_dir, "masks")
views = sorted(f[:-4] for f in os.listdir(mask_dir) if f.endswith(".png"))
masks = {v: np.array(Image.open(os.path.join(mask_dir, v + ".png"))) for v in views}
rng = random.Random(seed)
os.makedirs(out, exist_ok=True)


def interior(mask, oid):
    inside = mask == oid
    inner = inside.copy()
    for dy in range(-3, 4):
        for dx in range(-3, 4):
            inner &= np.roll(np.roll(inside, dy, 0), dx, 1)
    return np.nonzero(inner)


results = []
for t in range(n):
    prompt = {"objects": []}
    for oid, name in objects:
        for _ in range(1000):
            view = rng.choice(views)
            ys, xs = interior(masks[view], oid)
            if len(ys) > 20:
                break
        else:
            sys.exit(f"click_sweep: object {name} has no pixel 3 px inside its mask in any view")
        k = rng.randrange(len(ys))
        prompt["objects"].append({"id": oid, "name": name, "clicks": [
            {"positive": True, "u": float(xs[k]), "v": float(ys[k]), "view": view}]})
    run = os.path.join(out, f"p{t:03d}")
    os.makedirs(run, exist_ok=True)
    json.dump(prompt, open(os.path.join(run, "prompts.json"), "w"), indent=1)
    subprocess.run([pg, "segment", os.path.join(scene_dir, "scene.ply"), "--cameras", os.path.join(scene_dir, "cameras.json"),
                    "--prompts", os.path.join(run, "prompts.json"), "--views", "none", "--out", os.path.join(run, "pred", scene)]
                   + extra, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    subprocess.run([pg, "eval", "--gt", suite, "--pred", os.path.join(run, "pred"), "--split", "all", "--json",
                    os.path.join(run, "eval.json")], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    scored = json.load(open(os.path.join(run, "eval.json")))["scenes"][0]["3d"]["objects"]
    iou = {o["id"]: o["iou"] for o in scored}
    results.append([iou.get(oid, 0.0) for oid, _ in objects])
    print(f"p{t:03d} " + " ".join(f"{name} {iou.get(oid, 0.0):.3f}" for oid, name in objects), flush=True)
for j, (oid, name) in enumerate(objects):
    v = [r[j] for r in results]
    print(f"{name}: mean {statistics.mean(v):.3f}, median {statistics.median(v):.3f}, min {min(v):.3f}")
