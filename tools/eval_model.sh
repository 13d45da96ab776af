#!/usr/bin/env bash
# Evaluates an interactive model on the test split of freshly generated instance suites (seeds
# no training run has seen): the paper's table (3D IoU, 2D mIoU, OA) from the benchmark's first
# clicks (`pointgauss prompts` -> `segment`), and IoU@k / NoC@t from simulated 20-click sessions
# (`pointgauss clicks`), all scored by `pointgauss eval`. Writes OUT_DIR/<suite>.md, .json and
# <suite>-clicks.png (IoU against the number of clicks). DECODER (environment) picks the decoder
# for both: ptv3 (default: the network alone, the model card's protocol) or ptv3+graph.
# usage: [DECODER=ptv3|ptv3+graph] tools/eval_model.sh MODEL OUT_DIR [SCENES] [SEED] [DENSITY]
set -euo pipefail
model=${1:?usage: $0 MODEL OUT_DIR [SCENES] [SEED] [DENSITY]}
out=${2:?usage: $0 MODEL OUT_DIR [SCENES] [SEED] [DENSITY]}
scenes=${3:-10}; seed=${4:-202}; density=${5:-0.15}; decoder=${DECODER:-ptv3}
pg="$(cd "$(dirname "$0")/.." && pwd)/build/app/pointgauss"
mkdir -p "$out"
for suite in desk vehicles residence; do
  gt="$out/gt-$suite"
  [ -f "$gt/suite.json" ] || "$pg" synth --suite "$suite" --scenes "$scenes" --seed "$seed" --density "$density" \
      --sh-degree 1 --cameras 24 --width 320 --height 240 --out "$gt" >/dev/null
  pred="$out/pred-$suite"
  rm -rf "$pred"
  # The test split's scene names, from suite.json's "split": {"test": [...]}.
  tests=$(awk '/"test": *\[/ {on=1; next} on && /\]/ {on=0} on {gsub(/[", ]/, ""); print}' "$gt/suite.json")
  for scene in $tests; do
    "$pg" prompts "$gt/$scene" --out "$out/$suite-$scene.prompts.json" >/dev/null
    "$pg" segment "$gt/$scene/scene.ply" --cameras "$gt/$scene/cameras.json" --prompts "$out/$suite-$scene.prompts.json" \
        --model "$model" --decoder "$decoder" --out "$pred/$scene" >/dev/null
  done
  "$pg" clicks --gt "$gt" --model "$model" --decoder "$decoder" --out "$pred" --split test
  "$pg" eval --gt "$gt" --pred "$pred" --split test --json "$out/$suite.json" --plot "$out/$suite-clicks.png" \
      | tee "$out/$suite.md"
done
