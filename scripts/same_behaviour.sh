#!/usr/bin/env bash
# Trains the four runs that pin the trainers' behaviour (issue 38: a refactoring must leave them
# byte-identical) with the splat-train of BUILD, into OUT:
#   splat-1t   lego400, 600 iterations, 1 thread        splat-2t  the same, 2 threads
#   nerf       lego400, NeRF, 300 iterations            batch2    600 iterations, --batch 2
# Compare two OUT folders with scripts/same_behaviour_compare.py.
#   bash scripts/same_behaviour.sh BUILD OUT [DATA]     (DATA: ../shared/data/lego400)
set -euo pipefail
build=$1 out=$2
data=${3:-"$(dirname "$0")/../../shared/data/lego400"}
train=$(find "$build" -name splat-train -type f -perm -u+x | head -1)
mkdir -p "$out"
run() { local name=$1; shift; "$train" --data "$data" --out "$out/$name" --quiet "$@"; echo "$name done"; }
run splat-1t --iters 600 --threads 1
run splat-2t --iters 600 --threads 2
run nerf --method nerf --iters 300 --threads 2
run batch2 --iters 600 --batch 2 --threads 2
