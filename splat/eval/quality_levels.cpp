#include "splat/eval/quality_levels.hpp"

#include <cmath>

namespace splat {

std::vector<QualityLevel> quality_levels(const std::vector<ScorePoint>& scores) {
  std::vector<QualityLevel> levels;
  if (scores.empty() || !std::isfinite(scores.front().psnr)) return levels;
  // The first score's own level is no news (it says only "by the first score"); levels
  // start at the next whole dB above it.
  double next = std::floor(scores.front().psnr) + 1.0;
  double previous_seconds = scores.front().seconds;
  for (std::size_t k = 1; k < scores.size(); ++k) {
    const ScorePoint& s = scores[k];
    if (!std::isfinite(s.psnr)) break;
    for (; s.psnr >= next; next += 1.0) levels.push_back({next, s.iteration, s.seconds, previous_seconds});
    previous_seconds = s.seconds;
  }
  return levels;
}

}  // namespace splat
