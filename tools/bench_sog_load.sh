#!/usr/bin/env bash
# Decode time of a bundled SOG: `pointgauss bench load` beside PlayCanvas splat-transform's own
# reader (its readFile on the same bytes, in one Node process), medians of RUNS, and the ratio.
# Needs node and npm (splat-transform 2.7.1 goes into a temporary folder) and a built pointgauss.
#   bash tools/bench_sog_load.sh SCENE.sog [RUNS] [build/app/pointgauss]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sog=$(realpath "$1")
runs=${2:-7}
pg=${3:-$root/build/app/pointgauss}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm init -y >/dev/null && npm install --silent @playcanvas/splat-transform@2.7.1 >/dev/null)
cat > "$work/bench.mjs" <<'JS'
import { readFileSync } from 'node:fs';
import { readFile, MemoryReadFileSystem, logger } from '@playcanvas/splat-transform';
const [path, runs] = [process.argv[2], Number(process.argv[3])];
if (logger.setRenderer) logger.setRenderer({ handle() {} });  // no progress bars in the timing
const ms = [];
let rows = 0;
for (let r = 0; r < runs; ++r) {
    const t0 = performance.now();
    const fs = new MemoryReadFileSystem();
    fs.set('scene.sog', new Uint8Array(readFileSync(path)));
    const tables = await readFile({ filename: 'scene.sog', inputFormat: 'sog', options: {}, params: [], fileSystem: fs });
    rows = tables[0].numRows;
    ms.push(performance.now() - t0);
}
ms.sort((a, b) => a - b);
const median = runs % 2 ? ms[(runs - 1) / 2] : (ms[runs / 2 - 1] + ms[runs / 2]) / 2;
console.log(JSON.stringify({ gaussians: rows, median_ms: median }));
JS
st=$(cd "$work" && node bench.mjs "$sog" "$runs" 2>/dev/null | tail -1)
ours=$("$pg" bench load "$sog" --runs "$runs" --json)
python3 - "$st" "$ours" "$sog" "$runs" <<'PY'
import json, sys
st, ours = json.loads(sys.argv[1]), json.loads(sys.argv[2])
print("| %s (%d Gaussians, SH %d), median of %s | ms |" % (sys.argv[3].split("/")[-1], ours["gaussians"], ours["sh_degree"], sys.argv[4]))
print("|---|---:|")
print("| splat-transform 2.7.1 readFile, in Node | %.1f |" % st["median_ms"])
print("| pointgauss bench load | %.1f |" % ours["median_ms"])
print("| ratio (splat-transform / pointgauss) | %.2f |" % (st["median_ms"] / ours["median_ms"]))
assert st["gaussians"] == ours["gaussians"], "the two readers disagree on the count"
PY
