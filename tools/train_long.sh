#!/usr/bin/env bash
# A long interactive-model training, resumable: synthesizes the training suites once, then starts
# the run or resumes it from its checkpoint (OUT_DIR/NAME.ckpt.safetensors, written every 50
# steps), so the same command carries it across sessions, interruptions and reboots. Runs niced:
# it takes the cores only when nothing else wants them. The trainer is a copy of the build's
# binary (OUT_DIR/pointgauss), made on the first start, so rebuilding the repository mid-run
# changes nothing. Progress goes to OUT_DIR/NAME.train.log.
# usage: tools/train_long.sh OUT_DIR [NAME] [train options...]
#   e.g. nohup tools/train_long.sh /work/pg-train feat6k --features all --steps 6000 &
# Defaults, unless given: --config tiny --batch 2 --clicks 2 --lr 0.002 --lovasz 1 --val-every 500.
# SEEDS (default "101 103 105") are the training suites' seeds; the first one's test splits validate.
set -euo pipefail
out=${1:?usage: $0 OUT_DIR [NAME] [train options...]}
name=${2:-model}
shift $(( $# < 2 ? $# : 2 ))
mkdir -p "$out"
out=$(cd "$out" && pwd)
# One run per folder: a second would write the same checkpoint.
exec 9> "$out/.train_long.lock"
flock -n 9 || { echo "train_long: another run holds $out" >&2; exit 1; }
pg="$out/pointgauss"
[ -x "$pg" ] || cp "$(cd "$(dirname "$0")/.." && pwd)/build/app/pointgauss" "$pg"
data="$out/data"
seeds=(${SEEDS:-101 103 105})
for seed in "${seeds[@]}"; do
  for suite in desk vehicles residence; do
    n=$([ "$suite" = desk ] && echo 40 || echo 30)
    [ -f "$data/s$seed/$suite/suite.json" ] || nice -n 19 "$pg" synth --suite $suite --scenes $n --seed $seed \
        --density 0.15 --sh-degree 1 --cameras 8 --previews 1 --out "$data/s$seed/$suite" >/dev/null
  done
done
args=(--data "$data"/s*/* --val "$data/s${seeds[0]}/desk" "$data/s${seeds[0]}/vehicles" "$data/s${seeds[0]}/residence"
      --checkpoint-every 50 --out "$out/$name.safetensors" "$@")
# The defaults the caller did not give (the trainer refuses an option twice).
for default in "--config tiny" "--batch 2" "--clicks 2" "--lr 0.002" "--lovasz 1" "--val-every 500"; do
  case " $* " in *" ${default%% *} "*) ;; *) args+=($default) ;; esac
done
ckpt="$out/$name.ckpt.safetensors"
if [ -f "$ckpt" ]; then
  nice -n 19 "$pg" train "${args[@]}" --resume "$ckpt" >> "$out/$name.train.log" 2>&1
else
  nice -n 19 "$pg" train "${args[@]}" >> "$out/$name.train.log" 2>&1
fi
