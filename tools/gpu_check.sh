#!/usr/bin/env bash
# The checks to run when a real Vulkan GPU is at hand, in one go (a few minutes): the benches that
# the README's GPU table quotes (PTv3 forward and training step, render and a graph-decoder click at
# 150 k / 500 k / 6 M Gaussians, whole `segment` runs, `segment --semantic` scored by
# `eval`), then every test case with the validation layer on (a validation message fails a test).
# Usage: tools/gpu_check.sh OUT_DIR   (needs a Release build in build/ and ../shared/data/real;
# PG_DEVICE picks the device, default: the best GPU; GPU_CHECK_TEST_SECONDS caps the tests).
# Everything goes to OUT_DIR/log.txt as it runs, and the tests' output to OUT_DIR/tests.txt.
set -uo pipefail
cd "$(dirname "$0")/.."
out=$(mkdir -p "${1:?usage: tools/gpu_check.sh OUT_DIR}" && cd "$1" && pwd)
exec > >(tee "$out/log.txt") 2>&1
pg=$PWD/build/app/pointgauss
scene=../shared/data/real/guitar.ply
[ -x "$pg" ] || { echo "gpu_check: $pg: not built" >&2; exit 1; }
[ -f "$scene" ] || scene=../shared/data/real/guitar.compressed.ply
[ -f "$scene" ] || { echo "gpu_check: ../shared/data/real: no guitar scene" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
t0=$(date +%s)
stamp() { echo "=== [$(($(date +%s) - t0)) s] $*"; }
# One timed step: its output's tail, exit code and wall seconds.
step() {
    local limit=$1; shift
    stamp "$*"
    local a; a=$(date +%s.%N)
    timeout "$limit" "$@" 2>&1 | grep -v '^\s*$' | tail -40
    echo "  (exit ${PIPESTATUS[0]}, $(awk "BEGIN{printf \"%.2f\", $(date +%s.%N) - $a}") s)"
}

stamp "device check"
if ! "$pg" bench ptv3 --model small --points 1024 --repeats 1 --warmup 0 >/dev/null 2>&1; then
    VK_LOADER_DEBUG=error,warn "$pg" bench ptv3 --model small --points 1024 --repeats 1 2>&1 | head -30
    exit 1
fi

step 60 "$pg" bench ptv3 --model paper --points 8192 --repeats 5
step 60 "$pg" bench train --config small --points 8192 --clouds 2 --repeats 5

"$pg" orbit "$scene" --up -y --count 8 --elevation 15 --out "$tmp/orbit.json" >/dev/null
step 60 "$pg" bench render "$scene" --cameras "$tmp/orbit.json" --views all --frames 20

# A click with the graph decoder as the README's lavapipe figures measure it (150 k and 500 k tiles
# of the guitar), then the 6 M SH-3 scene's frame and click (issue 15's ratio).
guitar=assets/real/guitar
for n in 150000 500000 6000000; do
    sh=0; [ $n = 6000000 ] && sh=3
    build/tools/tile_scene "$scene" "$tmp/t$n.ply" --count $n --sh $sh --up y >/dev/null
    "$pg" orbit "$tmp/t$n.ply" --up -y --count 4 --elevation 20 --width 960 --height 720 --out "$tmp/o$n.json" >/dev/null
    step 120 "$pg" bench render "$tmp/t$n.ply" --cameras "$tmp/o$n.json" --views all --frames 5
    step 150 "$pg" bench segment "$tmp/t$n.ply" --cameras $guitar/cameras.json --prompts $guitar/label_prompts.json \
        --decoder graph --repeats 5
    rm -f "$tmp/t$n.ply"
done

sample=assets/sample/desk_000
step 90 "$pg" segment $sample/scene.ply --cameras $sample/cameras.json --prompts $sample/prompts.json \
    --decoder ptv3+graph --out "$tmp/sample"
step 90 "$pg" segment "$scene" --cameras $guitar/cameras.json --prompts $guitar/label_prompts.json --up -y \
    --decoder graph --out "$tmp/guitar"

"$pg" synth --suite campus --scenes 1 --seed 913 --out "$tmp/campus" >/dev/null
step 120 "$pg" segment "$tmp/campus/campus_000/scene.ply" --cameras "$tmp/campus/campus_000/cameras.json" --semantic \
    --out "$tmp/pred/campus_000"
step 60 "$pg" eval --gt "$tmp/campus" --pred "$tmp/pred" --split all

# Every test case as its own CTest test, validation on (a message fails the test); the viewer's need
# a display and the discrete-memory reruns test paths a discrete GPU takes anyway.
stamp "tests (validation on)"
limit=${GPU_CHECK_TEST_SECONDS:-240}
PG_VALIDATION=1 timeout $((limit + 30)) ctest --test-dir build -j"$(nproc)" --timeout "$limit" \
    -E '^(viewer|discrete memory)' --output-on-failure >"$out/tests.txt" 2>&1
grep -E 'tests passed|Failed|\*\*\*|Timeout|Not Run' "$out/tests.txt" | tail -40
stamp done
