#!/usr/bin/env bash
# Writes tests/fixtures/sog/: small SOG scenes of every layout and version, each beside the PLY
# that PlayCanvas's splat-transform decodes from it (the reference the reader must match to 1e-4).
#   bundled_sh3.sog                     v2, bundled, SH 3      (splat-transform base.ply X.sog)
#   unbundled_sh1/meta.json             v2, unbundled, SH 1
#   v1_sh2/meta.json                    v1, unbundled, SH 2    (tools/make_sog_v1.py; splat-transform
#                                       writes only v2 now, but still reads v1)
#   streamed/lod-meta.json              v2 chunks, 2 levels + environment, SH 0 (-l 0 / -l 1 / -l -1)
#   *.decoded.ply, streamed_decoded/    splat-transform's decode of each scene and chunk
# The scenes are cut from a synthetic desk (seed 4242) with tools/ply_every_nth.py. Needs node and
# npm (splat-transform is installed into a temporary folder), cwebp (Debian's `webp`) and a built
# pointgauss. Tests never run this: they read the committed output.
#   bash tools/make_sog_fixtures.sh [build/app/pointgauss]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
pg=${1:-$root/build/app/pointgauss}
out=$root/tests/fixtures/sog
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm init -y >/dev/null && npm install --silent @playcanvas/splat-transform@2.7.1 >/dev/null)
st() { "$work/node_modules/.bin/splat-transform" -q -w -g cpu "$@"; }

PG_DEVICE=${PG_DEVICE:-llvmpipe} "$pg" synth --suite desk --scenes 1 --seed 4242 --density 0.025 --sh-degree 3 \
  --cameras 4 --previews 1 --out "$work/synth" >/dev/null
scene=$work/synth/desk_000/scene.ply
nth() { python3 "$root/tools/ply_every_nth.py" "$scene" "$work/$1" "$2" "$3"; }
nth base.ply 8 0
nth fine.ply 4 1
nth coarse.ply 24 3
nth env.ply 97 5

rm -rf "$out" && mkdir -p "$out"
cd "$out"
st "$work/base.ply" bundled_sh3.sog
st bundled_sh3.sog bundled_sh3.decoded.ply
mkdir unbundled_sh1
st "$work/base.ply" -H 1 unbundled_sh1/meta.json
st unbundled_sh1/meta.json unbundled_sh1.decoded.ply
st "$work/base.ply" -H 2 "$work/base_sh2.ply"
python3 "$root/tools/make_sog_v1.py" "$work/base_sh2.ply" v1_sh2
st v1_sh2/meta.json v1_sh2.decoded.ply
st "$work/fine.ply" -H 0 -l 0 "$work/coarse.ply" -H 0 -l 1 "$work/env.ply" -H 0 -l -1 -C 1 -X 1 streamed/lod-meta.json
mkdir streamed_decoded
for meta in streamed/*/meta.json; do
  chunk=$(basename "$(dirname "$meta")")
  st "$meta" "streamed_decoded/$chunk.ply"
done
du -sh "$out"
