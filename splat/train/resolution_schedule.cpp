#include "splat/train/resolution_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>

#include "splat/core/error.hpp"

namespace splat {

namespace {

constexpr std::size_t kProfileSize = std::size_t(SpectrumProfile::kMaxScale - 1) * SpectrumProfile::kStepsPerUnit + 1;

// |F| of the image's luminance: rows, then columns, transformed in place.
std::vector<double> fourier_magnitude(const Image& image) {
  const int w = image.width, h = image.height, channels = image.channels;
  std::vector<std::complex<double>> spectrum(std::size_t(w) * h);
  const int colour = std::min(channels, 3);
  for (std::size_t p = 0; p < spectrum.size(); ++p) {
    double sum = 0;
    for (int c = 0; c < colour; ++c) sum += image.data[p * channels + c];
    spectrum[p] = sum / colour;
  }
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> line_in, line_out;
  line_in.resize(std::size_t(w));
  for (int y = 0; y < h; ++y) {
    std::copy_n(&spectrum[std::size_t(y) * w], w, line_in.begin());
    fft.fwd(line_out, line_in);
    std::copy_n(line_out.begin(), w, &spectrum[std::size_t(y) * w]);
  }
  line_in.resize(std::size_t(h));
  for (int x = 0; x < w; ++x) {
    for (int y = 0; y < h; ++y) line_in[std::size_t(y)] = spectrum[std::size_t(y) * w + x];
    fft.fwd(line_out, line_in);
    for (int y = 0; y < h; ++y) spectrum[std::size_t(y) * w + x] = line_out[std::size_t(y)];
  }
  std::vector<double> magnitude(spectrum.size());
  for (std::size_t p = 0; p < spectrum.size(); ++p) magnitude[p] = std::abs(spectrum[p]);
  return magnitude;
}

// Signed frequency of DFT index i of n: 0, 1, ..., then the negative half.
int signed_frequency(int i, int n) { return 2 * i <= n ? i : i - n; }

}  // namespace

SpectrumProfile spectrum_profile(const Image& image) {
  if (image.width < 2 || image.height < 2 || image.channels < 1)
    throw ArgumentError("spectrum_profile: an image of at least 2×2 pixels is needed");
  const std::vector<double> magnitude = fourier_magnitude(image);
  const int w = image.width, h = image.height;
  // An image reduced by s keeps |fx| < w/(2s) and |fy| < h/(2s): a frequency is kept while
  // s < its cutoff min(w/(2|fx|), h/(2|fy|)). kept_until[k] gathers the magnitude that is
  // kept for the samples below k and lost from sample k on.
  std::vector<double> kept_until(kProfileSize + 1, 0.0);
  double total = 0;
  for (int y = 0; y < h; ++y) {
    const int fy = std::abs(signed_frequency(y, h));
    for (int x = 0; x < w; ++x) {
      const int fx = std::abs(signed_frequency(x, w));
      const double cutoff = std::min(fx == 0 ? 1e30 : 0.5 * w / fx, fy == 0 ? 1e30 : 0.5 * h / fy);
      // Samples k with scale_at(k) < cutoff; every frequency counts at full size (k = 0).
      const double samples = std::ceil((cutoff - 1.0) * SpectrumProfile::kStepsPerUnit);
      const std::size_t kept = std::size_t(std::clamp(samples, 1.0, double(kProfileSize)));
      const double m = magnitude[std::size_t(y) * w + x];
      kept_until[kept] += m;
      total += m;
    }
  }
  SpectrumProfile profile;
  profile.share.assign(kProfileSize, 0.0);
  double lost_by_now = 0;  // magnitude of the frequencies lost at or before sample k
  for (std::size_t k = 0; k < kProfileSize; ++k) {
    lost_by_now += kept_until[k];
    profile.share[k] = total > 0 ? 1.0 - lost_by_now / total : 1.0;
  }
  return profile;
}

ResolutionSchedule::ResolutionSchedule(const ResolutionScheduleSettings& settings,
                                       std::span<const Image* const> images)
    : settings_(settings) {
  if (settings.max_divisor < 1) throw ArgumentError("resolution schedule: the largest divisor must be >= 1");
  if (settings.shape != ResolutionShape::kSpectrum || settings.max_divisor == 1 || settings.until <= 0) return;
  if (images.empty()) throw ArgumentError("resolution schedule: the spectrum shape needs training images");
  // The start: the smallest size at which every image keeps a quarter of its spectrum, and
  // no smaller than 1/max_divisor.
  const double quarter = 0.25;
  std::size_t start = std::min(kProfileSize - 1, std::size_t(std::min(settings.max_divisor, SpectrumProfile::kMaxScale) - 1) *
                                                     SpectrumProfile::kStepsPerUnit);
  share_.assign(kProfileSize, 0.0);
  for (const Image* image : images) {
    const SpectrumProfile profile = spectrum_profile(*image);
    std::size_t keeps_quarter = 0;
    while (keeps_quarter + 1 < kProfileSize && profile.share[keeps_quarter + 1] >= quarter) ++keeps_quarter;
    start = std::min(start, keeps_quarter);
    for (std::size_t k = 0; k < kProfileSize; ++k) share_[k] += profile.share[k] / double(images.size());
  }
  share_.resize(start + 1);
  start_share_ = share_.back();
}

int ResolutionSchedule::divisor(double schedule_iteration) const {
  const ResolutionScheduleSettings& s = settings_;
  if (s.max_divisor <= 1 || schedule_iteration > s.until) return 1;
  if (s.shape == ResolutionShape::kHalving) {
    int levels = 0;
    while ((1 << (levels + 1)) <= s.max_divisor) ++levels;  // halvings from max_divisor down to 1
    const int iteration = int(schedule_iteration);
    const int stage = int(std::int64_t(std::max(0, iteration - 1)) * levels / std::max(1, s.until));
    return std::max(1, s.max_divisor >> stage);
  }
  if (share_.empty()) return 1;
  // The smallest size (largest scale) holding start_share^(1 − τ) of the spectrum.
  const double phase = std::clamp(schedule_iteration / double(s.until), 0.0, 1.0);
  const double target = std::pow(start_share_, 1.0 - phase);
  std::size_t k = share_.size() - 1;
  while (k > 0 && share_[k] < target) --k;
  // Half size until `until` (see the header), unless the spectrum starts above it.
  const int start = int(std::floor(SpectrumProfile::scale_at(share_.size() - 1)));
  return std::max({1, std::min(2, start), int(std::floor(SpectrumProfile::scale_at(k)))});
}

std::vector<std::pair<int, int>> ResolutionSchedule::steps() const {
  std::vector<std::pair<int, int>> steps{{0, divisor(0)}};
  for (int iteration = 1; iteration <= settings_.until + 1; ++iteration)
    if (const int d = divisor(iteration); d != steps.back().second) steps.emplace_back(iteration, d);
  return steps;
}

}  // namespace splat
