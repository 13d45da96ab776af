#!/usr/bin/env bash
# A long scripted viewer session on the bundled sample under Xvfb: cycles of new objects, clicks
# (positive and negative), undo / redo, hide, delete, camera moves and exports, ACTIONS in all
# (default 520). The viewer logs host RSS and live device memory after each action settles
# (--script-log); the summary fails if either memory's envelope grew by more than 10 % over the
# last 30 % of the run (see below).
# Usage: tools/viewer_soak.sh OUT_DIR [ACTIONS]   (needs a build in build/ and xvfb-run)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: tools/viewer_soak.sh OUT_DIR [ACTIONS]}
actions=${2:-520}
mkdir -p "$out"
viewer=./build/app/viewer/pointgauss-viewer
script="$out/soak.json"

# Click points on the sample's first camera (fractions of the picture) that land on objects.
points=("0.6,0.62" "0.385,0.37" "0.49,0.2" "0.3,0.6" "0.7,0.45" "0.55,0.5")
{
  echo '{"actions": [{"snap": 0}'
  n=1 cycle=0
  while [ $n -lt "$actions" ]; do
    p=${points[$((cycle % ${#points[@]}))]}
    q=${points[$(((cycle + 3) % ${#points[@]}))]}
    step=(
      "{\"new_object\": \"soak_$cycle\"}" "{\"click\": [$p]}" "{\"click\": [$q], \"negative\": true}"
      '{"undo": 1}' '{"redo": 1}' '{"hide": true}' '{"hide": false}' '{"orbit": [15, 0]}'
    )
    # Every other cycle's object is deleted again; every eighth cycle exports.
    [ $((cycle % 2)) -eq 1 ] && step+=('{"delete": true}')
    [ $((cycle % 8)) -eq 7 ] && step+=("{\"export\": {\"folder\": \"$out/export\", \"masks\": false}}")
    for a in "${step[@]}"; do
      [ $n -lt "$actions" ] || break
      echo ", $a"
      n=$((n + 1))
    done
    cycle=$((cycle + 1))
  done
  echo ']}'
} > "$script"

start=$(date +%s)
xvfb-run -a -s "-screen 0 1280x800x24" "$viewer" assets/sample/desk_000/scene.ply --script "$script" \
  --script-log "$out/soak.log.jsonl" --size 960x640
echo "$(wc -l < "$out/soak.log.jsonl") actions settled in $(($(date +%s) - start)) s"

# The envelope must not grow: the largest value in the last 30 % of the actions against the
# largest in the 30 % before them (the first 40 % are warm-up: objects accumulate until the
# walk's label columns and the viewer's buffers reach their working size).
awk -F'[:,}]' '
  { for (i = 1; i < NF; i++) { if ($i ~ /"host_rss"/) rss[NR] = $(i + 1); if ($i ~ /"device_live"/) dev[NR] = $(i + 1) } }
  END {
    n = NR; if (n < 100) { print "soak: too few actions to judge (" n ")"; exit 1 }
    a = int(0.4 * n); b = int(0.7 * n)
    for (i = a + 1; i <= n; i++) {
      if (i <= b) { if (rss[i] > r1) r1 = rss[i]; if (dev[i] > d1) d1 = dev[i] }
      else { if (rss[i] > r2) r2 = rss[i]; if (dev[i] > d2) d2 = dev[i] }
    }
    printf "host RSS: largest %.1f MiB over actions %d-%d, %.1f MiB over %d-%d (%+.1f %%)\n", r1 / 1048576, a, b, r2 / 1048576, b, n, 100 * (r2 - r1) / r1
    printf "device memory: largest %.1f MiB over actions %d-%d, %.1f MiB over %d-%d (%+.1f %%)\n", d1 / 1048576, a, b, d2 / 1048576, b, n, 100 * (d2 - d1) / d1
    exit (r2 > 1.1 * r1 || d2 > 1.1 * d1) ? 1 : 0
  }' "$out/soak.log.jsonl"
