#!/usr/bin/env bash
# PSNR of SOG against the PLY it was made from, for both writers side by side: pointgauss convert
# and PlayCanvas splat-transform (2.7.1, -g cpu), each rendered by pointgauss over the same orbit
# (VIEWS views, SIZE x SIZE) and compared with the PLY's renders (tools/psnr.py). Also prints
# file sizes and write times. Needs node/npm and a built pointgauss.
#   bash tools/sog_psnr.sh SCENE.ply [VIEWS] [SIZE] [build/app/pointgauss]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
scene=$(realpath "$1")
views=${2:-8}
size=${3:-360}
pg=${4:-$root/build/app/pointgauss}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm init -y >/dev/null && npm install --silent @playcanvas/splat-transform@2.7.1 >/dev/null)
cd "$work"
"$pg" orbit "$scene" --out orbit.json --count "$views" --width "$size" --height "$size" --up -y >/dev/null
t0=$(date +%s.%N)
node_modules/.bin/splat-transform -q -w -g cpu "$scene" theirs.sog
t1=$(date +%s.%N)
"$pg" convert "$scene" ours.sog >/dev/null
t2=$(date +%s.%N)
for s in ply:"$scene" theirs:theirs.sog ours:ours.sog; do
  "$pg" render "${s#*:}" --cameras orbit.json --out "r_${s%%:*}" >/dev/null 2>&1
done
# splat-transform must read our file: its decode of ours.sog, rendered, must match ours.
node_modules/.bin/splat-transform -q -w ours.sog ours_by_splat_transform.ply
"$pg" render ours_by_splat_transform.ply --cameras orbit.json --out r_ours_st >/dev/null 2>&1
echo "| writer | PSNR vs PLY (mean of $views views, ${size}x${size}) | size | write s |"
echo "|---|---:|---:|---:|"
printf "| splat-transform 2.7.1 (-g cpu) | %s | %s | %.1f |\n" "$(python3 "$root/tools/psnr.py" r_ply r_theirs | tail -1 | cut -d' ' -f2)" \
  "$(du -h theirs.sog | cut -f1)" "$(echo "$t1 - $t0" | bc)"
printf "| pointgauss convert | %s | %s | %.1f |\n" "$(python3 "$root/tools/psnr.py" r_ply r_ours | tail -1 | cut -d' ' -f2)" \
  "$(du -h ours.sog | cut -f1)" "$(echo "$t2 - $t1" | bc)"
echo "splat-transform's decode of our file against ours: $(python3 "$root/tools/psnr.py" r_ours r_ours_st | tail -1)"
