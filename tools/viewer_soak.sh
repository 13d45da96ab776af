#!/usr/bin/env bash
# A long scripted viewer session on the bundled sample under Xvfb: cycles of new objects, clicks
# (positive and negative), undo / redo, hide, delete, camera moves and exports, ACTIONS in all
# (default 520). The viewer logs host RSS and live device memory after each action settles
# (--script-log); the summary compares the rest of the run with the state after warm-up (the
# first 50 actions) and fails if either grew by more than 10 %.
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

# After warm-up (action 50) against the largest later value and the last, for both memories.
awk -F'[:,}]' '
  { for (i = 1; i < NF; i++) { if ($i ~ /"host_rss"/) rss = $(i + 1); if ($i ~ /"device_live"/) dev = $(i + 1) }
    n++; if (n == 50) { rss0 = rss; dev0 = dev }
    if (n > 50) { if (rss > rssmax) rssmax = rss; if (dev > devmax) devmax = dev } }
  END {
    if (n <= 50) { print "soak: too few actions to judge (" n ")"; exit 1 }
    printf "host RSS after warm-up %.1f MiB, largest later %.1f MiB (%+.1f %%), last %.1f MiB\n", rss0 / 1048576, rssmax / 1048576, 100 * (rssmax - rss0) / rss0, rss / 1048576
    printf "device memory after warm-up %.1f MiB, largest later %.1f MiB (%+.1f %%), last %.1f MiB\n", dev0 / 1048576, devmax / 1048576, 100 * (devmax - dev0) / dev0, dev / 1048576
    exit (rssmax > 1.1 * rss0 || devmax > 1.1 * dev0) ? 1 : 0
  }' "$out/soak.log.jsonl"
