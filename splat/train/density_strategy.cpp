#include "splat/train/density_strategy.hpp"

#include "splat/core/error.hpp"
#include "splat/train/compact_strategy.hpp"
#include "splat/train/official_strategy.hpp"
#include "splat/train/points_near_bounds.hpp"
#include "splat/train/training_config.hpp"

namespace splat {

CompactSettings compact_settings_for(const CompactSettings& configured, const Dataset& dataset) {
  CompactSettings settings = configured;
  // The decay and the view-share prune were chosen on real captures (issue 40); synthetic
  // data keeps the resets and its few-view Gaussians, as the holdout and the near-points
  // prune leave it untouched.
  if (configured.real_capture_only && !dataset.points) {
    settings.opacity_decay = 0.0f;
    settings.prune_min_view_share = 0.0f;
  }
  return settings;
}

std::unique_ptr<DensityStrategy> make_density_strategy(const SplatTrainingConfig& config,
                                                       const Dataset& dataset,
                                                       std::size_t gaussian_count) {
  if (config.strategy == "official")
    return std::make_unique<OfficialStrategy>(config.density, gaussian_count);
  if (config.strategy == "compact") {
    const CompactSettings settings = compact_settings_for(config.compact, dataset);
    return std::make_unique<CompactStrategy>(
        settings, config.density, dataset.train.size(), config.seed, gaussian_count,
        settings.prune_before_points > 0 ? points_near_bounds(dataset) : std::vector<CameraNearBound>{});
  }
  throw ArgumentError("unknown density strategy '" + config.strategy + "'");
}

}  // namespace splat
