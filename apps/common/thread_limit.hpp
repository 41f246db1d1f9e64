#pragma once
// --threads N for every tool: oneTBB's worker count capped for as long as the returned
// object lives. Results never depend on it (docs/DESIGN.md); only the speed does.
#include <memory>
#include <tbb/global_control.h>

namespace splat::cli {

// threads ≤ 0: no limit (all cores); the result is then empty.
inline std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(threads));
}

}  // namespace splat::cli
