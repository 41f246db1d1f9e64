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
  if (config.strategy == "compact")
    return std::make_unique<CompactStrategy>(
        config.compact, config.density, dataset.train.size(), config.seed, gaussian_count,
        config.compact.prune_before_points > 0 ? points_near_bounds(dataset) : std::vector<CameraNearBound>{});
  throw ArgumentError("unknown density strategy '" + config.strategy + "'");
}

}  // namespace splat
