#!/usr/bin/env bash
# Peer benchmark: render a 3DGS scene with Spark (three.js) in headless Chromium on SwiftShader
# (software WebGL2) and report ms per finished, sorted frame; compare with
# `pointgauss bench render` on lavapipe in the same run. See README.md in this folder.
#
#   tools/bench_spark/bench_spark.sh SCENE.ply CAMERAS.json --width W --height H \
#       [--views all|i,j] [--frames N] [--warmup N] [--json] [--save DIR]
#
# Installs what it lacks, quietly: Debian's chromium (apt, as root) and the pinned npm
# packages (npm ci in this folder).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

case " $* " in
    *" -h "* | *" --help "*) exec node "$here/bench_spark.mjs" --help ;;
esac

if ! command -v node >/dev/null 2>&1; then
    echo "bench_spark: node (>= 20) is needed" >&2
    exit 2
fi
node_major="$(node -p 'process.versions.node.split(".")[0]')"
if [ "$node_major" -lt 20 ]; then
    echo "bench_spark: node >= 20 is needed (playwright-core), found $(node --version)" >&2
    exit 2
fi

# Browser: Debian's chromium; Playwright's own browser download is not used.
if [ ! -x /usr/lib/chromium/chromium ] && ! command -v chromium >/dev/null 2>&1; then
    if [ "$(id -u)" -ne 0 ]; then
        echo "bench_spark: chromium is missing; run as root or: sudo apt-get install -y chromium" >&2
        exit 2
    fi
    echo "bench_spark: installing chromium (apt)" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    apt-get install -y -qq chromium >/dev/null
fi

# npm packages pinned by package-lock.json; reinstalled when missing or the lock changed.
stamp="$here/node_modules/.bench_spark_lock"
if [ ! -f "$stamp" ] || ! cmp -s "$here/package-lock.json" "$stamp"; then
    echo "bench_spark: npm ci" >&2
    (cd "$here" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
    cp "$here/package-lock.json" "$stamp"
fi

exec node "$here/bench_spark.mjs" "$@"
