#!/usr/bin/env bash
# Issue 14's rasterizer benchmarks for two builds, alternating A B A B so that both see the
# same machine: the conformance model at 800² and 400², a large trained model at 800²,
# splat-grad's forward + backward at 400² (with the official gradients compared), and the
# viewer's orbit at 800×600. Needs xvfb-run for the viewer.
#   bash bench/raster_ab.sh BUILD_A BUILD_B LARGE_MODEL.ply [ROUNDS] [OUT_DIR]
# BUILD_A/B are build folders (with tools/ and viewer/). Prints each run's summary lines,
# labelled; the raw output stays in OUT_DIR (default: a temporary folder, removed).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 3 ]; then sed -n 2,8p "$0" >&2; exit 2; fi
build_a="$1" build_b="$2" large="$3" rounds="${4:-3}"
shared="${SPLAT_SHARED_DIR:-../shared}"
conf="$shared/conformance"
if [ -n "${5:-}" ]; then out="$5"; mkdir -p "$out"; else out="$(mktemp -d)"; trap 'rm -rf "$out"' EXIT; fi
for round in $(seq "$rounds"); do
  for side in A B; do
    build="$build_a"; [ "$side" = B ] && build="$build_b"
    render() {  # MODEL CAMERAS SIZE REPEATS LABEL
      "$build/bin/splat-render" --model "$1" --cameras "$2" --width "$3" --height "$3" \
        --out "$out/render_$side" --bench "$4" --threads 2 > "$out/$5_$side.$round" 2>&1
      echo "$5 $side round $round: $(grep -E 'median|per frame:' "$out/$5_$side.$round" | tr '\n' ' ')"
    }
    render "$conf/lego_subset50k.ply" "$conf/transforms_test.json" 800 10 conformance800
    render "$conf/lego_subset50k.ply" "$conf/transforms_test.json" 400 10 conformance400
    render "$large" "$shared/data/lego400/transforms_test.json" 800 5 large800
    "$build/bin/splat-grad" --model "$conf/lego_subset50k.ply" --cameras "$conf/transforms_test.json" \
      --view 0 --width 400 --height 400 --bg 1,1,1 --weights "$conf/gradients/W_r_0.f32" \
      --out "$out/grad_$side.f32" --compare "$conf/gradients/grad_r_0.f32" --bench 20 > "$out/grad_$side.$round" 2>&1
    echo "grad $side round $round: $(grep -E '^bench|relative error' "$out/grad_$side.$round" | tr -s ' ' | tr '\n' ';')"
    xvfb-run -a -s '-screen 0 1920x1200x24' "$build/bin/splat-viewer" "$large" --width 800 --height 600 \
      --bench-orbit 10 > "$out/viewer_$side.$round" 2>&1
    echo "viewer $side round $round: $(grep '"full"' "$out/viewer_$side.$round")"
  done
done
