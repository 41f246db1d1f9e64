#!/usr/bin/env bash
# Web formats against the PLY: converts MODEL.ply to .spz at several SH bit depths and to
# .splat (splat-convert), renders every frame of CAMERAS.json at W x H from each and from the
# PLY (splat-render), and prints each file's size and splat-psnr's min / mean against the
# PLY's renders. bench/README.md "Your own photos and web formats" has today's figures.
#   bash bench/web_format_bench.sh MODEL.ply CAMERAS.json W H OUT [BITS ...]   (BITS e.g. 6,6; default 5,4 6,6 8,8)
set -euo pipefail
if [ $# -lt 5 ]; then sed -n 2,6p "$0"; exit 2; fi
bin="$(cd "$(dirname "$0")/.." && pwd)/build/bin"
model=$1 cameras=$2 width=$3 height=$4 out=$5
shift 5
variants=("$@")
if [ ${#variants[@]} -eq 0 ]; then variants=(5,4 6,6 8,8); fi
mkdir -p "$out"
"$bin/splat-render" --model "$model" --cameras "$cameras" --width "$width" --height "$height" --out "$out/ply" > /dev/null
compare() {  # FILE: render it and print its size and PSNR against the PLY's renders
  local file=$1 name; name=$(basename "$file" | tr . _)
  "$bin/splat-render" --model "$file" --cameras "$cameras" --width "$width" --height "$height" --out "$out/$name" > /dev/null
  echo "$(basename "$file"): $(stat -c %s "$file") bytes (PLY $(stat -c %s "$model")): $("$bin/splat-psnr" "$out/ply" "$out/$name" | tail -1)"
}
for bits in "${variants[@]}"; do
  "$bin/splat-convert" "$model" "$out/model_${bits/,/_}.spz" --spz-sh-bits "$bits" > /dev/null
  compare "$out/model_${bits/,/_}.spz"
done
"$bin/splat-convert" "$model" "$out/model.splat" > /dev/null
compare "$out/model.splat"
