#!/usr/bin/env bash
# The README's test command: installs dependencies, builds, runs the whole test suite.
#   SPLAT_SANITIZE=ON bash scripts/test.sh   runs it under AddressSanitizer + UBSan instead.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
sanitize="${SPLAT_SANITIZE:-OFF}"
build_dir="build"
if [ "$sanitize" = "ON" ]; then
  build_dir="build-asan"
  export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
fi
cmake -S . -B "$build_dir" -G Ninja -DSPLAT_SANITIZE="$sanitize" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j "$(nproc)"
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)"
