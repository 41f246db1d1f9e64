#!/usr/bin/env bash
# The three methods side by side (issue 43): one splat-eval comparison per dataset, each method
# trained for the same budget, then one table of them all. On an otherwise idle machine:
#
#   bash bench/method_table.sh OUT DATASET...
#
#   DATASET     a scene of scenes/ by name (default, depth_range, few_views, fine_texture,
#               shiny, simple, thin_structures; rendered into OUT/scenes/ first), or a folder
#               of ../shared/data by name (real_thermos, ...), trained at --downscale
#               REAL_DOWNSCALE (default 2)
#   SECONDS     training budget per method (default 600); METHODS (default splat,nerf,ngp)
#
# Each dataset takes about three budgets plus scoring (35 minutes at the default). A dataset
# whose OUT/<name>/results.json exists is skipped, so the script can be run again to go on.
# Then prints the table (also with no DATASET: the table of what OUT holds).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: bench/method_table.sh OUT DATASET...}
shift
seconds=${SECONDS_PER_METHOD:-600}
methods=${METHODS:-splat,nerf,ngp}
real_downscale=${REAL_DOWNSCALE:-2}
mkdir -p "$out"

for name in "$@"; do
  if [ -f "$out/$name/results.json" ]; then
    echo "$name: done before, skipped"
    continue
  fi
  extra=()
  if [ -f "scenes/$name.json" ]; then
    data="$out/scenes/$name"
    [ -d "$data" ] || build/bin/splat-scene render "scenes/$name.json" --out "$data" > /dev/null
  elif [ -d "../shared/data/$name" ]; then
    data="../shared/data/$name"
    extra=(--downscale "$real_downscale")
  else
    echo "unknown dataset '$name': neither scenes/$name.json nor ../shared/data/$name" >&2
    exit 2
  fi
  echo "$(date +%T) $name: splat-eval --methods $methods --max-seconds $seconds ${extra[*]}"
  build/bin/splat-eval --data "$data" --out "$out/$name" --methods "$methods" --max-seconds "$seconds" \
    "${extra[@]}" --quiet > "$out/$name.log" 2>&1 || echo "  failed: see $out/$name.log"
done

python3 - "$out" <<'EOF'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
rows = []
for results in sorted(out.glob("*/results.json")):
    r = json.loads(results.read_text())
    cells = {}
    for m in r["methods"]:
        cells[m["method"]] = "%.2f dB, SSIM %.3f, %s it, %.1f MB" % (
            m["final"]["psnr"], m["final"]["ssim"], format(m["iterations"], ","), m["model_bytes"] / 1e6)
    rows.append((results.parent.name, r["budget_seconds"], cells))
methods = []
for _, _, cells in rows:
    methods += [m for m in cells if m not in methods]
print("| dataset | budget | " + " | ".join(methods) + " |")
print("|---|---|" + "---|" * len(methods))
for name, budget, cells in rows:
    print("| %s | %d s | %s |" % (name, budget, " | ".join(cells.get(m, "") for m in methods)))
EOF
