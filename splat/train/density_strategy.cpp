#include "splat/train/density_strategy.hpp"

#include "splat/core/error.hpp"
#include "splat/train/compact_strategy.hpp"
#include "splat/train/official_strategy.hpp"
#include "splat/train/training_config.hpp"

namespace splat {

std::unique_ptr<DensityStrategy> make_density_strategy(const SplatTrainingConfig& config,
                                                       std::size_t train_views,
                                                       std::size_t gaussian_count) {
  if (config.strategy == "official")
    return std::make_unique<OfficialStrategy>(config.density, gaussian_count);
  if (config.strategy == "compact")
    return std::make_unique<CompactStrategy>(config.compact, config.density, train_views,
                                             config.seed, gaussian_count);
  throw ArgumentError("unknown density strategy '" + config.strategy + "'");
}

}  // namespace splat
