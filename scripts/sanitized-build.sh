#!/usr/bin/env bash
# scripts/sanitized-build.sh [TARGET...]: configures and builds build-sanitize/ with clang:
# AddressSanitizer + UndefinedBehaviorSanitizer and libFuzzer's coverage (SPLAT_FUZZ=ON), the
# tests included, at -O2 -g1 (line tables: what stack traces need) without NDEBUG (our
# assertions and Eigen's bounds checks stay on).
# The sanitizer suite (scripts/test.sh --sanitize) and the fuzz campaign (bench/fuzz.sh) share
# this one build. With TARGETs, builds only those. Source it for the sanitizers' settings.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=build-sanitize
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DSPLAT_FUZZ=ON -DSPLAT_BUILD_TESTS=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1" \
  > "$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 2; }
if [ $# -gt 0 ]; then
  cmake --build "$build" -j "$(nproc)" --target "$@"
else
  cmake --build "$build" -j "$(nproc)"
fi
