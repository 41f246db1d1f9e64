#pragma once
// splat-eval's three kinds of run. Each writes its own JSON into options.out (last, so a
// JSON present means its run finished); the charts and report.html are then drawn from
// whichever of those files the folder holds.
#include "eval_command.hpp"

namespace splat::cli {

// Both methods, same budget, scored over time: results.json, splat/, nerf/, grids/.
void run_comparison(const EvalCommandOptions& options, const Dataset& dataset);

// Both methods under each stability condition, scored at the end: stability.json and
// stability/<condition>/<method>/<model>.
void run_stability(const EvalCommandOptions& options, const Dataset& dataset);

// The splat method under each Gaussian budget: sweep.json and sweep/<budget>/model.ply.
void run_gaussian_sweep(const EvalCommandOptions& options, const Dataset& dataset);

}  // namespace splat::cli
