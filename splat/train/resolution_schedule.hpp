#pragma once
// Which image size each iteration trains at: early iterations fit the coarse content of the
// images, which a smaller image holds as well as the full one, at a fraction of the cost
// (the blend and its backward grow with the pixels).
//
// Two shapes, both reaching full size at schedule iteration `until`:
// - halving: 1/max_divisor at first, the divisor halving at equal steps;
// - spectrum: the image size grows with the share of the training images' spectrum it
//   holds, as DashGaussian (Chen et al., CVPR 2025) schedules it. An image reduced by s
//   keeps the frequencies below 1/s of the full band; e(s) is the share of the images'
//   summed Fourier magnitude there. Training starts at the largest s that keeps a quarter
//   (capped by max_divisor) and at phase τ = iteration/until trains at the smallest size
//   holding e_start^(1−τ): equal steps in log-energy, so the size rises slowly while the
//   low frequencies still dominate and fast at the end. It stays at half size or less until
//   `until`: the spectrum alone reaches full size well before (lego400: at 70 % of the
//   warm-up), and the compact strategy's growth, which runs through the warm-up, then
//   grows markedly fewer Gaussians than at half size (scenes/thin_structures at 7,000
//   iterations: 5,043 against 11,872 and 0.26 dB lower; bench/HISTORY.md, issue 39).
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "splat/core/image.hpp"

namespace splat {

enum class ResolutionShape : std::uint8_t { kHalving, kSpectrum };

struct ResolutionScheduleSettings {
  ResolutionShape shape = ResolutionShape::kHalving;
  int max_divisor = 1;  // 1 = full size throughout
  int until = 0;        // schedule iteration from which the full size is trained
};

// The share of an image's summed Fourier magnitude (of its luminance, DC included) that an
// image reduced by s still holds, sampled at s = 1, 1 + 1/kSteps, ... up to kMaxScale.
struct SpectrumProfile {
  static constexpr int kStepsPerUnit = 16;
  static constexpr int kMaxScale = 8;
  std::vector<double> share;  // [(kMaxScale − 1)·kStepsPerUnit + 1], share[0] = 1, decreasing

  static double scale_at(std::size_t index) { return 1.0 + double(index) / kStepsPerUnit; }
};

SpectrumProfile spectrum_profile(const Image& image);

class ResolutionSchedule {
 public:
  ResolutionSchedule() = default;
  // `images` are needed by the spectrum shape only (a few spread over the training views
  // are enough: the schedule follows their mean profile).
  ResolutionSchedule(const ResolutionScheduleSettings& settings, std::span<const Image* const> images);

  // 1 = full size, 2 = half width and height, ...
  int divisor(double schedule_iteration) const;

  // The divisor the schedule starts at (for the log).
  int start_divisor() const { return divisor(0); }
  int until() const { return settings_.until; }

  // Where the divisor changes: (schedule iteration, divisor from there on), from 0 to the
  // full size.
  std::vector<std::pair<int, int>> steps() const;

 private:
  ResolutionScheduleSettings settings_;
  std::vector<double> share_;  // the mean profile (spectrum shape)
  double start_share_ = 1.0;
};

}  // namespace splat
