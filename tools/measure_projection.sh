#!/usr/bin/env bash
# Measures the pipeline around the network with the ground-truth decoder: for each instance
# suite, generates scenes, writes the benchmark's first clicks, segments them with both label
# projection modes, with and without refinement, and prints `pointgauss eval`'s 2D mIoU.
# usage: tools/measure_projection.sh OUT_DIR [SCENES] [CAMERAS] [WIDTH] [HEIGHT]
set -euo pipefail
out=${1:?usage: $0 OUT_DIR [SCENES] [CAMERAS] [WIDTH] [HEIGHT]}
scenes=${2:-1}; cameras=${3:-24}; width=${4:-320}; height=${5:-240}
pg="$(cd "$(dirname "$0")/.." && pwd)/build/app/pointgauss"
mkdir -p "$out"
for suite in desk vehicles residence; do
  gt="$out/$suite"
  [ -f "$gt/suite.json" ] || "$pg" synth --suite "$suite" --scenes "$scenes" --seed 11 --cameras "$cameras" \
      --width "$width" --height "$height" --out "$gt" >/dev/null
  for mode in occlusion paper; do
    for refine in refine no-refine; do
      pred="$out/pred-$suite-$mode-$refine"
      rm -rf "$pred"
      for scene_dir in "$gt"/*_[0-9][0-9][0-9]; do
        scene=$(basename "$scene_dir")
        "$pg" prompts "$scene_dir" --out "$out/$scene.prompts.json" >/dev/null
        flag=""; [ "$refine" = no-refine ] && flag="--no-refine"
        "$pg" segment "$scene_dir/scene.ply" --cameras "$scene_dir/cameras.json" --prompts "$out/$scene.prompts.json" \
            --model ground-truth --mode "$mode" $flag --out "$pred/$scene" >/dev/null 2>&1
      done
      row=$("$pg" eval --gt "$gt" --pred "$pred" --split all --json "$pred.json" | grep '\*\*mean\*\*')
      echo "$suite $mode $refine $row"
    done
  done
done
