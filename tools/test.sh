#!/usr/bin/env bash
# Installs, builds and runs the whole test suite on lavapipe with the validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
bash tools/build.sh
export PG_DEVICE=${PG_DEVICE:-llvmpipe} PG_VALIDATION=1
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 900
