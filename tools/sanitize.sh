#!/usr/bin/env bash
# Builds PointGauss with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and runs
# the test suite there (lavapipe, validation on), or the tests matching REGEX.
# Usage: tools/sanitize.sh [REGEX]
# Any sanitizer report fails the test it happens in (halt_on_error, and UBSan aborts too).
# Leak checking is off: the Vulkan loader, the validation layer and lavapipe's LLVM keep
# process-lifetime allocations that LeakSanitizer reports at exit; our own resources are RAII
# and their release is what the device-memory tests check.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build-asan -j"$(nproc)"
export PG_DEVICE=${PG_DEVICE:-llvmpipe} PG_VALIDATION=1
export ASAN_OPTIONS=detect_leaks=0:halt_on_error=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
args=(--test-dir build-asan --output-on-failure -j"$(nproc)" --timeout 3600)
[ $# -gt 0 ] && args+=(-R "$1")
ctest "${args[@]}"
