#pragma once
// splat-eval's methods, by the names --methods and results.json use:
//   splat           Gaussian splatting with the compact density strategy
//   splat-official  Gaussian splatting with the official 3DGS density control
//   nerf            the NeRF baseline (MLPs on a positional encoding)
//   ngp             the NeRF with Instant-NGP's multiresolution hash encoding
// and how a training run of one is set up from the command's options.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "apps/splat-eval/eval_command.hpp"
#include "apps/splat-eval/method_run.hpp"

namespace splat::cli {

inline const char* const kEvalMethods[] = {"splat", "splat-official", "nerf", "ngp"};

// The density strategy of a splat method ("compact" | "official"); none for "nerf" and "ngp";
// ArgumentError naming the known methods for any other name.
std::optional<std::string> splat_strategy(const std::string& method);

// What options.mode runs, in order: options.methods, or the mode's default (comparison: every
// method; stability: splat and nerf; sweep: splat). ArgumentError for an unknown or repeated
// name, or when the sweep is given anything but one splat method.
std::vector<std::string> methods_to_run(const EvalCommandOptions& options);

// --splat-config FILE: its settings, checked (InputError naming the file). A "strategy" key
// would reset every splat method to that one strategy, so it is dropped with a warning: the
// method names the strategy, and the file's other settings apply over that strategy's preset.
nlohmann::json read_splat_settings(const std::filesystem::path& file);

// The trainer settings of `method`: for a splat method its strategy's preset with
// options.splat_settings over it, for the NeRF options.nerf_config, for NGP options.ngp_config; then splat-eval's own
// (the dataset's background; no test points or checkpoints: the loop scores).
MethodRunRequest method_request(const EvalCommandOptions& options, const std::string& method,
                                const std::filesystem::path& out_dir);

}  // namespace splat::cli
