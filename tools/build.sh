#!/usr/bin/env bash
# Configures and builds PointGauss into build/ (Release with assertions off).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=${PG_BUILD_TYPE:-Release} >/dev/null
cmake --build build -j"$(nproc)"
