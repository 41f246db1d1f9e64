#include "apps/splat-eval/eval_methods.hpp"

#include <algorithm>
#include <cstdio>

#include "splat/train/config_file.hpp"
#include "splat/core/error.hpp"

namespace splat::cli {

std::optional<std::string> splat_strategy(const std::string& method) {
  if (method == "splat") return "compact";
  if (method == "splat-official") return "official";
  if (method == "nerf" || method == "ngp") return std::nullopt;
  std::string known;
  for (const char* name : kEvalMethods) known += std::string(known.empty() ? "" : ", ") + name;
  throw ArgumentError("--methods: unknown method '" + method + "' (known: " + known + ")");
}

std::vector<std::string> methods_to_run(const EvalCommandOptions& options) {
  for (auto it = options.methods.begin(); it != options.methods.end(); ++it) {
    splat_strategy(*it);  // known names only
    if (std::find(options.methods.begin(), it, *it) != it)
      throw ArgumentError("--methods names " + *it + " twice");
  }
  switch (options.mode) {
    case EvalMode::kComparison:
      if (!options.methods.empty()) return options.methods;
      return {std::begin(kEvalMethods), std::end(kEvalMethods)};
    case EvalMode::kStability:
      // Seven conditions per method: the default keeps the two kinds of model.
      return options.methods.empty() ? std::vector<std::string>{"splat", "nerf"} : options.methods;
    case EvalMode::kGaussianSweep:
      if (options.methods.empty()) return {"splat"};
      if (options.methods.size() != 1 || !splat_strategy(options.methods.front()))
        throw ArgumentError("--sweep-gaussians trains one splat method: give --methods splat or "
                            "--methods splat-official");
      return options.methods;
  }
  return {};
}

nlohmann::json read_splat_settings(const std::filesystem::path& file) {
  nlohmann::json settings = read_config_json(file);
  SplatTrainingConfig check;
  apply_config_json(file, settings, check);
  if (settings.contains("strategy")) {
    std::fprintf(stderr,
                 "warning: %s: \"strategy\" ignored; each splat method has its own (splat: compact, "
                 "splat-official: official), and the file's other settings apply over it\n",
                 file.string().c_str());
    settings.erase("strategy");
  }
  return settings;
}

MethodRunRequest method_request(const EvalCommandOptions& options, const std::string& method,
                                const std::filesystem::path& out_dir) {
  MethodRunRequest request;
  request.method = method;
  if (const auto strategy = splat_strategy(method)) {
    request.splat_config = splat_training_preset(*strategy);
    from_json(options.splat_settings, request.splat_config);
  }
  const bool ngp = method == "ngp";
  request.nerf_config = ngp ? options.ngp_config : options.nerf_config;
  // The budget is the NeRF's limit, as splat-train's --max-seconds (train/main.cpp).
  if (request.nerf_config.iterations == nerf_training_preset(request.nerf_config.method).iterations)
    request.nerf_config.iterations = kNerfIterationsUnderBudget;
  std::copy(options.dataset.background, options.dataset.background + 3, request.splat_config.background);
  std::copy(options.dataset.background, options.dataset.background + 3, request.nerf_config.background);
  // The budget is the only limit that matters here; the loop scores.
  request.splat_config.test_interval = request.nerf_config.test_interval = 0;
  request.splat_config.checkpoint_interval = request.nerf_config.checkpoint_interval = 0;
  request.budget_seconds = options.max_seconds;
  request.out_root = options.out;
  request.out_dir = out_dir;
  return request;
}

}  // namespace splat::cli
