#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz: every scene, camera, prompts, model and viewer-script
# reader, under Address/UndefinedBehaviorSanitizer) into build-fuzz/ with clang and runs each for
# SECONDS (default 60), as many at once as there are cores. Corpora grow in build-fuzz/corpus/T/,
# seeded from the fixtures and the malformed corpora; a crashing input lands in
# build-fuzz/findings/T/ and the run ends non-zero. Usage: tools/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
has_fuzzer() { command -v clang++ >/dev/null && echo 'int main(){}' | clang++ -x c++ -fsanitize=fuzzer-no-link - -o /dev/null 2>/dev/null; }
if ! has_fuzzer; then  # Debian 12's clang and its libFuzzer runtime
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get install -y clang libclang-rt-14-dev >/dev/null
fi
has_fuzzer || { echo "fuzz.sh: clang with libFuzzer is not available (apt-get install clang libclang-rt-14-dev)" >&2; exit 1; }
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DPG_FUZZ=ON -DBUILD_TESTING=OFF >/dev/null
cmake --build build-fuzz --target pg_fuzz_all -j"$(nproc)"

targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_scene_ply fuzz_scene_splat fuzz_scene_spz fuzz_scene_sog fuzz_cameras_json fuzz_transforms_json
                                   fuzz_colmap_bin fuzz_colmap_txt fuzz_prompts fuzz_model fuzz_viewer_script fuzz_batch_jobs)
mal=tests/fixtures/malformed
seed() {  # target -> seed files
  case $1 in
    fuzz_scene_ply) ls $mal/scenes/*.ply; find tests/fixtures -name '*.ply' -size -64k ;;
    fuzz_scene_splat) ls $mal/scenes/*.splat 2>/dev/null || true ;;
    fuzz_scene_spz) ls $mal/scenes/*.spz 2>/dev/null || true ;;
    fuzz_scene_sog) ls $mal/scenes/*.sog tests/fixtures/sog/*.sog 2>/dev/null || true ;;
    fuzz_cameras_json) echo assets/sample/desk_000/cameras.json; ls $mal/cameras/inria_*.json $mal/cameras/json_*.json ;;
    fuzz_transforms_json) ls $mal/cameras/ns_*.json ;;
    fuzz_prompts) echo assets/sample/desk_000/prompts.json; find assets/real -name '*prompts*.json' ;;
    fuzz_model) find tests/fixtures -name '*.safetensors' -size -256k ;;
    fuzz_viewer_script) find tests app -name '*.json' -path '*script*' 2>/dev/null || true ;;
    fuzz_batch_jobs) echo assets/sample/jobs.json ;;
  esac
}
pids=() names=()
status=0
run_one() {
  local t=$1 corpus=build-fuzz/corpus/$1 findings=build-fuzz/findings/$1
  mkdir -p "$corpus" "$findings"
  for f in $(seed "$t"); do [ -f "$f" ] && cp -n "$f" "$corpus/" 2>/dev/null || true; done
  case $t in  # the COLMAP targets take cameras and images as one input: a 4-byte length, then both
    fuzz_colmap_bin|fuzz_colmap_txt)
      local ext=${t#fuzz_colmap_}
      for d in assets/sample/desk_000/sparse/0 $mal/cameras/*; do
        [ -f "$d/cameras.$ext" ] && [ -f "$d/images.$ext" ] || continue
        python3 -c 'import sys,struct; a=open(sys.argv[1],"rb").read(); b=open(sys.argv[2],"rb").read(); open(sys.argv[3],"wb").write(struct.pack("<I",len(a))+a+b)' \
          "$d/cameras.$ext" "$d/images.$ext" "$corpus/seed-$(basename "$d")"
      done ;;
  esac
  local tmp
  tmp=$(mktemp -d)
  TMPDIR=$tmp ./build-fuzz/tests/fuzz/"$t" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 \
    -max_len=1048576 -artifact_prefix="$findings/" -print_final_stats=1 > "build-fuzz/$t.log" 2>&1 || { rm -rf "$tmp"; return 1; }
  rm -rf "$tmp"
}
for t in "${targets[@]}"; do
  run_one "$t" &
  pids+=($!) names+=("$t")
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do sleep 1; done
done
for i in "${!pids[@]}"; do
  t=${names[$i]}
  if wait "${pids[$i]}"; then r=ok; else r=FOUND; status=1; fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "build-fuzz/$t.log" | grep -o '[0-9]*$' || echo 0)
  echo "$t: $r, $runs executions in ${seconds} s (log build-fuzz/$t.log, findings build-fuzz/findings/$t/)"
done
exit $status
