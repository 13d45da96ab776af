#!/usr/bin/env bash
# The checks to run when a real Vulkan GPU is at hand, in one go (a few minutes): the benches that
# the README's GPU table quotes (PTv3 forward and training step, render at 90 k / 1.5 M / 6 M
# Gaussians, a click with the graph decoder, whole `segment` runs, `segment --semantic` scored by
# `eval`), then every test binary with the validation layer on (a validation message fails a test).
# Usage: tools/gpu_check.sh OUT_DIR   (needs a Release build in build/ and ../shared/data/real;
# PG_DEVICE picks the device, default: the best GPU; GPU_CHECK_TEST_SECONDS caps the tests).
# Everything goes to OUT_DIR/log.txt as it runs, and each test binary's output to OUT_DIR/tests/.
set -uo pipefail
cd "$(dirname "$0")/.."
out=$(mkdir -p "${1:?usage: tools/gpu_check.sh OUT_DIR}" && cd "$1" && pwd)
mkdir -p "$out/tests"
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
step 60 "$pg" bench ptv3 --model small --points 8192 --repeats 5
step 60 "$pg" bench train --config tiny --points 8192 --clouds 2 --repeats 5
step 60 "$pg" bench train --config small --points 8192 --clouds 2 --repeats 5

"$pg" orbit "$scene" --up -y --count 8 --elevation 15 --out "$tmp/orbit.json" >/dev/null
step 60 "$pg" bench render "$scene" --cameras "$tmp/orbit.json" --views all --frames 20
for n in 1500000 6000000; do
    build/tools/tile_scene "$scene" "$tmp/t$n.ply" --count $n --sh 3 --up y >/dev/null
    "$pg" orbit "$tmp/t$n.ply" --up -y --count 4 --elevation 20 --width 960 --height 720 --out "$tmp/o$n.json" >/dev/null
    step 120 "$pg" bench render "$tmp/t$n.ply" --cameras "$tmp/o$n.json" --views all --frames 5
    rm -f "$tmp/t$n.ply"
done

guitar=assets/real/guitar
build/tools/tile_scene "$scene" "$tmp/t150k.ply" --count 150000 --up y >/dev/null
step 90 "$pg" bench segment "$tmp/t150k.ply" --cameras $guitar/cameras.json --prompts $guitar/label_prompts.json \
    --decoder graph --coarse-answer
sample=assets/sample/desk_000
step 90 "$pg" bench segment $sample/scene.ply --cameras $sample/cameras.json --prompts $sample/prompts.json
step 90 "$pg" segment $sample/scene.ply --cameras $sample/cameras.json --prompts $sample/prompts.json \
    --model assets/models/interactive.safetensors --out "$tmp/sample"
step 90 "$pg" segment "$scene" --cameras $guitar/cameras.json --prompts $guitar/label_prompts.json --up -y --out "$tmp/guitar"

"$pg" synth --suite campus --scenes 1 --seed 913 --out "$tmp/campus" >/dev/null
step 120 "$pg" segment "$tmp/campus/campus_000/scene.ply" --cameras "$tmp/campus/campus_000/cameras.json" --semantic \
    --out "$tmp/pred/campus_000"
step 60 "$pg" eval --gt "$tmp/campus" --pred "$tmp/pred" --split all

stamp "tests (validation on)"
limit=${GPU_CHECK_TEST_SECONDS:-240}
pids=()
for b in build/tests/pg_tests_*; do
    [ -x "$b" ] || continue
    name=$(basename "$b")
    # Each binary in its own folder's scratch; the validation layer's messages fail the test.
    (PG_VALIDATION=1 timeout "$limit" "$b" -r compact >"$out/tests/$name.txt" 2>&1
     echo "exit $?" >>"$out/tests/$name.txt") &
    pids+=($!)
done
wait "${pids[@]}"  # not a bare wait: it would also wait for the tee above, which never ends
for f in "$out"/tests/*.txt; do
    echo "$(basename "$f" .txt): $(grep -E '^(Passed|Failed|All tests)' "$f" | tail -1) ($(tail -1 "$f"))"
done
stamp done
