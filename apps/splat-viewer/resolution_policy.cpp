#include "apps/splat-viewer/resolution_policy.hpp"

#include <algorithm>

namespace splat::viewer {

ResolutionPolicy::ResolutionPolicy(std::vector<float> levels, double target_ms, bool progressive)
    : levels_(std::move(levels)), target_ms_(target_ms), progressive_(progressive) {
  std::sort(levels_.begin(), levels_.end());
  if (levels_.empty() || levels_.back() != 1.0f) levels_.push_back(1.0f);
}

void ResolutionPolicy::observe(float scale, double ms) {
  // Render time grows with the pixel count; the per-Gaussian part does not, so this
  // overestimates small scales' savings a little: the next observation corrects it.
  const double full = ms / std::max(1e-3, double(scale) * double(scale));
  full_ms_ = full_ms_ > 0 ? 0.5 * full_ms_ + 0.5 * full : full;
}

float ResolutionPolicy::next(bool moving, float shown_scale) const {
  if (moving) {
    // The largest level whose estimated time fits the target; the coarsest if none does.
    if (full_ms_ <= 0) return levels_.front();
    for (auto it = levels_.rbegin(); it != levels_.rend(); ++it)
      if (full_ms_ * double(*it) * double(*it) <= target_ms_) return *it;
    return levels_.front();
  }
  if (!progressive_) return 1.0f;
  // Still: one level finer than what is shown, up to full resolution.
  for (float level : levels_)
    if (level > shown_scale) return level;
  return 1.0f;
}

}  // namespace splat::viewer
