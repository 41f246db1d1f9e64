#include "splat/train/density_strategy.hpp"

#include "splat/core/error.hpp"
#include "splat/train/compact_strategy.hpp"
#include "splat/train/official_strategy.hpp"
#include "splat/train/points_near_bounds.hpp"
#include "splat/train/training_config.hpp"

namespace splat {

std::unique_ptr<DensityStrategy> make_density_strategy(const SplatTrainingConfig& config,
                                                       const Dataset& dataset,
                                                       std::size_t gaussian_count) {
  if (config.strategy == "official")
    return std::make_unique<OfficialStrategy>(config.density, gaussian_count);
  if (config.strategy == "compact") {
    // Both rules against near-camera floaters are for real captures, which a point cloud marks:
    // synthetic scenes show thin parts that few views draw, and keep them.
    CompactSettings settings = config.compact;
    if (!dataset.points) settings.prune_min_view_share = 0.0f;
    return std::make_unique<CompactStrategy>(
        settings, config.density, dataset.train.size(), config.seed, gaussian_count,
        settings.prune_before_points > 0 ? points_near_bounds(dataset) : std::vector<CameraNearBound>{});
  }
  throw ArgumentError("unknown density strategy '" + config.strategy + "'");
}

}  // namespace splat
