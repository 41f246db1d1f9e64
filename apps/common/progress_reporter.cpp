#include "apps/common/progress_reporter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace splat::cli {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const long s = long(std::lround(seconds));
  char buffer[32];
  if (s >= 3600)
    std::snprintf(buffer, sizeof(buffer), "%ldh%02ldm%02lds", s / 3600, (s / 60) % 60, s % 60);
  else if (s >= 60)
    std::snprintf(buffer, sizeof(buffer), "%ldm%02lds", s / 60, s % 60);
  else
    std::snprintf(buffer, sizeof(buffer), "%lds", s);
  return buffer;
}

ProgressReporter::ProgressReporter(bool interactive, double plain_interval_seconds)
    : interactive_(interactive), plain_interval_(plain_interval_seconds),
      last_print_(std::chrono::steady_clock::now() - std::chrono::hours(1)) {}

std::string progress_line(const ProgressSnapshot& s) {
  // Whichever limit comes first sets the estimate.
  double eta = s.iterations_per_second > 0
                   ? (s.total_iterations - s.iteration) / s.iterations_per_second
                   : INFINITY;
  if (s.max_seconds > 0) eta = std::min(eta, std::max(0.0, s.max_seconds - s.elapsed_seconds));
  char buffer[256];
  char psnr[64] = "";
  if (s.train_psnr) std::snprintf(psnr, sizeof(psnr), " | PSNR %.2f", *s.train_psnr);
  char test[64] = "";
  if (s.test_psnr) std::snprintf(test, sizeof(test), " | test %.2f dB", *s.test_psnr);
  // Done: the share of whichever limit is nearer.
  double done = double(s.iteration) / std::max(1, s.total_iterations);
  if (s.max_seconds > 0) done = std::max(done, std::min(1.0, s.elapsed_seconds / s.max_seconds));
  // The iteration count is shown out of its limit only while that limit may end the run: a
  // run that stops when its time is up (the NeRF under a budget) shows how far it got.
  const bool by_time = s.max_seconds > 0 && (s.max_seconds - s.elapsed_seconds) <
                                                (s.total_iterations - s.iteration) / std::max(1e-9, s.iterations_per_second);
  char iteration[48];
  if (by_time)
    std::snprintf(iteration, sizeof(iteration), "%d", s.iteration);
  else
    std::snprintf(iteration, sizeof(iteration), "%d/%d", s.iteration, s.total_iterations);
  std::snprintf(buffer, sizeof(buffer), "iter %s (%3.0f%%) | %.2f it/s | loss %.4f%s%s | %s | %s elapsed | ETA %s",
                iteration, 100.0 * done,
                s.iterations_per_second, s.loss, psnr, test, s.model_size.c_str(),
                format_duration(s.elapsed_seconds).c_str(), format_duration(eta).c_str());
  return buffer;
}

void ProgressReporter::update(const ProgressSnapshot& s, bool force) {
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (interactive_) {
    if (!force && since < 0.2) return;  // redraw at most five times a second
    std::printf("\r\033[K%s", progress_line(s).c_str());
    bar_drawn_ = true;
  } else {
    if (!force && since < plain_interval_) return;
    std::printf("%s\n", progress_line(s).c_str());
  }
  std::fflush(stdout);
  last_print_ = now;
}

void ProgressReporter::message(const std::string& text) {
  if (interactive_ && bar_drawn_) std::printf("\r\033[K");
  std::printf("%s\n", text.c_str());
  std::fflush(stdout);
  bar_drawn_ = false;
}

void ProgressReporter::finish() {
  if (interactive_ && bar_drawn_) std::printf("\n");
  std::fflush(stdout);
  bar_drawn_ = false;
}

}  // namespace splat::cli
