#!/usr/bin/env bash
# Builds the real guitar's benchmark suite from the shared capture and the committed polygons
# (assets/real/guitar): the hull labels (tools/label_hull), masks of every view rasterized from
# those labels, and the benchmark's first clicks. Usage: tools/make_guitar_suite.sh OUT_DIR
# (needs ../shared/data/real/guitar.ply and a build in build/).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: tools/make_guitar_suite.sh OUT_DIR}
scene=../shared/data/real/guitar.ply
assets=assets/real/guitar
[ -f "$scene" ] || { echo "make_guitar_suite: $scene: no such file" >&2; exit 1; }
rm -rf "$out"
build/tools/label_hull "$scene" --cameras $assets/cameras.json --polygons $assets/polygons.json --dilate 4 \
  --suite "$out" --name guitar
# Masks straight from the labels: the ground-truth decoder returns the labels as they are
# (no graph), one click per object is enough for it.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
build/app/pointgauss segment "$out/guitar/scene.ply" --cameras $assets/cameras.json --prompts $assets/label_prompts.json \
  --model ground-truth --decoder ptv3 --no-refine --up -y --out "$tmp/gt" >/dev/null
mv "$tmp/gt/masks" "$out/guitar/masks"
build/app/pointgauss prompts "$out/guitar" --out "$out/guitar_prompts.json" >/dev/null
echo "wrote $out (suite.json, guitar/, guitar_prompts.json)"
