#!/usr/bin/env bash
# Batches of views and MPI ranks (issue 18):
#
#   bash bench/batch_bench.sh OUT [quality|scenes|scaling]...
#
#   quality   lego400 at --batch 1, 2 and 4, LEGO_VIEWS views each (default 10,000: the
#             default schedule compressed to that length), one after another: batch 1 as one
#             process of 2 threads, batches 2 and 4 as 2 MPI ranks of one thread each (the
#             same models as one process would train, and a real run's exchange figures)
#   scenes    every scene in scenes/ at --batch 1, 2 and 4, SCENE_VIEWS views each (default
#             3,000), one thread each, two at a time
#   scaling   the cost of the exchange: lego400 from N random Gaussians (N in GAUSSIANS,
#             default "30000 100000 300000"; the official strategy, which does not densify
#             before view 500) for 200 views in batches of 4, as one process of 2 threads
#             and as 2 and 4 MPI ranks of one thread each (4 oversubscribe 2 cores). Wants
#             an idle machine.
#
# With no selection it runs them all. Then prints the tables: python3 bench/batch_tables.py OUT
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: bench/batch_bench.sh OUT [quality|scenes|scaling]...}
shift
selection=("$@")
[ ${#selection[@]} -eq 0 ] && selection=(quality scenes scaling)
train=${TRAIN:-$PWD/build/bin/splat-train}  # TRAIN=... compares another build
lego=../shared/data/lego400
lego_views=${LEGO_VIEWS:-10000}
scene_views=${SCENE_VIEWS:-3000}
read -r -a gaussians <<< "${GAUSSIANS:-30000 100000 300000}"
mkdir -p "$out"

source bench/run_lib.sh  # run NAME ARGS...

ranks() {  # ranks K NAME ARGS...: the same under mpirun with K ranks of one thread each
  local k=$1 name=$2
  shift 2
  echo "$(date +%T) $name: mpirun -np $k splat-train $*"
  env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
    mpirun -np "$k" --oversubscribe --bind-to none \
    "$train" --out "$out/$name" --checkpoint-every 0 --quiet --threads 1 "$@" > "$out/$name.log" 2>&1 ||
    echo "  failed: see $out/$name.log"
}

quality() {
  run lego-b1 --data "$lego" --batch 1 --iters "$lego_views" --threads 2
  ranks 2 lego-b2 --data "$lego" --batch 2 --iters "$lego_views"
  ranks 2 lego-b4 --data "$lego" --batch 4 --iters "$lego_views"
}

scenes() {
  [ -d "$out/scenes" ] || for s in default thin_structures simple fine_texture shiny few_views depth_range; do
    build/bin/splat-scene render "scenes/$s.json" --out "$out/scenes/$s" > /dev/null
  done
  for b in 1 2 4; do
    (for s in default thin_structures simple depth_range; do
       run "scene-$s-b$b" --data "$out/scenes/$s" --batch "$b" --iters "$scene_views" --threads 1 --test-every 0
     done) &
    (for s in fine_texture shiny few_views; do
       run "scene-$s-b$b" --data "$out/scenes/$s" --batch "$b" --iters "$scene_views" --threads 1 --test-every 0
     done) &
    wait
  done
}

scaling() {
  for n in "${gaussians[@]}"; do
    echo "{\"random_init_points\": $n}" > "$out/scaling-$n.json"
    local common=(--data "$lego" --strategy official --config "$out/scaling-$n.json" --batch 4 --iters 200
                  --test-every 0)
    run "scaling-$n-k1" "${common[@]}" --threads 2
    ranks 2 "scaling-$n-k2" "${common[@]}"
    ranks 4 "scaling-$n-k4" "${common[@]}"
  done
}

for job in "${selection[@]}"; do
  case "$job" in
    quality) quality ;;
    scenes) scenes ;;
    scaling) scaling ;;
    *) echo "unknown benchmark '$job'" >&2; exit 2 ;;
  esac
done
python3 bench/batch_tables.py "$out"
