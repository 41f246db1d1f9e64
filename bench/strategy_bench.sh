#!/usr/bin/env bash
# The density strategies' benchmarks (issue 13), one after another on an otherwise idle machine:
#
#   bash bench/strategy_bench.sh OUT [lego300|lego-full|official7k|scenes|real]...
#
#   lego300     splat-train on lego400 with default settings and --max-seconds 300
#   lego-full   the default run to its end, bounded by --max-seconds 2400
#   official7k  --strategy official --iters 7000 on lego400 (the official figures' guard)
#   scenes      every scene in scenes/ but depth_range, both strategies, SCENE_ITERS
#               iterations each (default 7000), two runs at a time with one thread each
#               (iteration-limited, so the pairing does not change the results)
#   real        the real captures of ../shared/data (BENCHMARKS.md P6), both strategies,
#               REAL_SECONDS each (default 600) at --downscale REAL_DOWNSCALE (default 2);
#               REAL_STRATEGIES="compact" re-runs one strategy only
#
# With no selection it runs them all (about four hours). Then prints the tables:
#   python3 bench/strategy_tables.py OUT
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: bench/strategy_bench.sh OUT [lego300|lego-full|official7k|scenes|real]...}
shift
selection=("$@")
[ ${#selection[@]} -eq 0 ] && selection=(lego300 lego-full official7k scenes real)
shared=../shared/data
train=build/bin/splat-train
scene_iters=${SCENE_ITERS:-7000}
real_seconds=${REAL_SECONDS:-600}
real_downscale=${REAL_DOWNSCALE:-2}
read -r -a real_strategies <<< "${REAL_STRATEGIES:-compact official}"
mkdir -p "$out"

source bench/run_lib.sh  # run NAME ARGS...

scenes() {
  [ -d "$out/scenes" ] || for s in default thin_structures simple fine_texture shiny few_views; do
    build/bin/splat-scene render "scenes/$s.json" --out "$out/scenes/$s" > /dev/null
  done
  for strategy in compact official; do
    # Two queues of three scenes, each run on one core.
    (for s in default thin_structures simple; do
       run "scene-$s-$strategy" --data "$out/scenes/$s" --strategy "$strategy" --iters "$scene_iters" \
         --threads 1 --test-every 0
     done) &
    (for s in fine_texture shiny few_views; do
       run "scene-$s-$strategy" --data "$out/scenes/$s" --strategy "$strategy" --iters "$scene_iters" \
         --threads 1 --test-every 0
     done) &
    wait
  done
}

for job in "${selection[@]}"; do
  case "$job" in
    lego300) run lego300 --data "$shared/lego400" --max-seconds 300 ;;
    lego-full) run lego-full --data "$shared/lego400" --max-seconds 2400 --test-every 1000 ;;
    official7k) run official7k --data "$shared/lego400" --strategy official --iters 7000 ;;
    scenes) scenes ;;
    real)
      for d in real_thermos real_thermos_distorted real_cup; do
        for strategy in "${real_strategies[@]}"; do
          run "real-$d-$strategy" --data "$shared/$d" --strategy "$strategy" --max-seconds "$real_seconds" \
            --downscale "$real_downscale" --test-every 1000
        done
      done ;;
    *) echo "unknown benchmark '$job'" >&2; exit 2 ;;
  esac
done
python3 bench/strategy_tables.py "$out"
