#!/usr/bin/env bash
# P3 (BENCHMARKS.md): render speed of the conformance model at 800x800 and 400x400.
# Each splat-render --bench run renders the 13 test views REPEATS times after a warm-up and
# reports the median; this script runs that RUNS times per size and prints every JSON line.
#   bash bench/render_bench.sh [REPEATS] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
repeats="${1:-10}"
runs="${2:-3}"
shared="${SPLAT_SHARED_DIR:-../shared}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for size in 800 400; do
  for run in $(seq "$runs"); do
    build/bin/splat-render --model "$shared/conformance/lego_subset50k.ply" \
      --cameras "$shared/conformance/transforms_test.json" --width "$size" --height "$size" \
      --out "$out" --bench "$repeats" | tail -n 1
  done
done
