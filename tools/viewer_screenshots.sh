#!/usr/bin/env bash
# Regenerates the README's viewer screenshots (assets/screenshots/) with the scripted mode under
# Xvfb: the bundled desk sample and, where ../shared is present, the real guitar scene, both
# segmented by the shipped model.
set -euo pipefail
cd "$(dirname "$0")/.."
viewer=./build/app/viewer/pointgauss-viewer
out=assets/screenshots
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
run() { xvfb-run -a -s "-screen 0 1600x1000x24" "$viewer" "$@" --size 1200x800; }

cat > "$tmp/desk.json" <<'JSON'
{"actions": [
  {"snap": 0},
  {"new_object": "box"}, {"click": [0.6, 0.62]},
  {"new_object": "plant"}, {"click": [0.385, 0.37]},
  {"new_object": "lamp"}, {"click": [0.49, 0.2]},
  {"tints": true}
]}
JSON
run assets/sample/desk_000/scene.ply --script "$tmp/desk.json" --screenshot "$out/viewer-desk.png"

guitar=../shared/data/real/guitar.ply
if [ -f "$guitar" ]; then
  cat > "$tmp/guitar.json" <<'JSON'
{"actions": [{"snap": 0}, {"new_object": "guitar"}, {"click": [0.5, 0.5]}]}
JSON
  run "$guitar" --script "$tmp/guitar.json" --screenshot "$out/viewer-guitar.png"
fi
ls -la "$out"
