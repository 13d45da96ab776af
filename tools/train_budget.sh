#!/usr/bin/env bash
# Trains an interactive model in the time a lease allows: synthesizes the training suites,
# times the first 100 steps (scene loading included), then resumes to as many steps as fit in
# the rest of the budget, so the OneCycle schedule still anneals before the time is up. Writes
# OUT_DIR/NAME.safetensors, its checkpoint (resumable anywhere with `train --resume`), log and
# curves. Meant for a GPU lent for minutes (a training step there is ~25x lavapipe's).
# usage: tools/train_budget.sh OUT_DIR SECONDS [NAME] [train options...]
#   e.g. tools/train_budget.sh out 420 small_feat --config small --features all
# DATA (default /tmp/pg-train-data) holds the suites; SEEDS (default "101 103 105") their seeds.
set -euo pipefail
out=${1:?usage: $0 OUT_DIR SECONDS [NAME] [train options...]}
budget=${2:?usage: $0 OUT_DIR SECONDS [NAME] [train options...]}
name=${3:-model}
shift $(( $# < 3 ? $# : 3 ))
pg="$(cd "$(dirname "$0")/.." && pwd)/build/app/pointgauss"
data=${DATA:-/tmp/pg-train-data}
t0=$(date +%s)
mkdir -p "$out" "$data"
pids=()
for seed in ${SEEDS:-101 103 105}; do
  for suite in desk vehicles residence; do
    n=$([ "$suite" = desk ] && echo 40 || echo 30)
    [ -f "$data/s$seed/$suite/suite.json" ] || "$pg" synth --suite $suite --scenes $n --seed $seed --density 0.15 \
        --sh-degree 1 --cameras 8 --previews 1 --out "$data/s$seed/$suite" >/dev/null &
    pids+=($!)
  done
done
for p in "${pids[@]}"; do wait "$p"; done
first=$(echo ${SEEDS:-101 103 105} | cut -d' ' -f1)
common=(--data "$data"/s*/* --val "$data/s$first/desk" "$data/s$first/vehicles" "$data/s$first/residence"
        --batch 2 --clicks 2 --lr 0.002 --lovasz 1 --val-every 250 --checkpoint-every 50 --out "$out/$name.safetensors")
echo "train_budget: data ready after $(( $(date +%s) - t0 )) s"
c0=$(date +%s)
"$pg" train "${common[@]}" "$@" --steps 1500 --stop-at 100
dt=$(( $(date +%s) - c0 )); [ $dt -lt 1 ] && dt=1
# The rest, less a margin for validation, BatchNorm calibration and writing.
left=$(( budget - ($(date +%s) - t0) - 30 ))
steps=$(( 100 + left * 100 / dt )); [ $steps -lt 101 ] && steps=101
echo "train_budget: 100 steps took $dt s; resuming to $steps steps"
"$pg" train "${common[@]}" "$@" --resume "$out/$name.ckpt.safetensors" --steps $steps
echo "train_budget: done after $(( $(date +%s) - t0 )) s"
