#pragma once
// splat-eval's three kinds of run. Each writes its own JSON into options.out (last, so a
// JSON present means its run finished); the charts and report.html are then drawn from
// whichever of those files the folder holds.
#include "apps/splat-eval/eval_command.hpp"

namespace splat::cli {

// The methods (--methods, default all three), same budget, scored over time: results.json,
// one folder per method (splat/, splat-official/, nerf/), grids/.
void run_comparison(const EvalCommandOptions& options, const Dataset& dataset);

// The methods (--methods, default splat and nerf) under each stability condition, scored at
// the end: stability.json and stability/<condition>/<method>/<model>.
void run_stability(const EvalCommandOptions& options, const Dataset& dataset);

// One splat method (splat unless --methods says splat-official) under each Gaussian budget:
// sweep.json and sweep/<budget>/model.ply.
void run_gaussian_sweep(const EvalCommandOptions& options, const Dataset& dataset);

}  // namespace splat::cli
