#!/usr/bin/env bash
# The README's test command: installs dependencies, builds, runs the whole test suite.
#   bash scripts/test.sh --sanitize   instead builds everything with clang under AddressSanitizer
#                                     + UBSan (build-sanitize/), runs the whole suite there, then
#                                     runs every fuzz target briefly (bench/fuzz.sh). CI runs both.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
if [ "${1:-}" = "--sanitize" ]; then
  bash scripts/sanitized-build.sh
  source scripts/sanitizer-options.sh
  ctest --test-dir build-sanitize --output-on-failure -j "$(nproc)"
  bash bench/fuzz.sh "${SPLAT_FUZZ_SECONDS:-5}"
  exit 0
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
ctest --test-dir build --output-on-failure -j "$(nproc)"
