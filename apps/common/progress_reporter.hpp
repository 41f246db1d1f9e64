#pragma once
// Training progress on stdout: a one-line bar redrawn in place on a terminal, plain periodic
// lines otherwise (logs, CI).
#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

namespace splat::cli {

struct ProgressSnapshot {
  int iteration = 0, total_iterations = 0;
  double elapsed_seconds = 0, max_seconds = 0;  // max 0 = no time limit
  double iterations_per_second = 0;
  double loss = 0;
  std::optional<double> train_psnr, test_psnr;
  std::string model_size;  // "250632 Gaussians", "0.20M parameters"
};

class ProgressReporter {
 public:
  explicit ProgressReporter(bool interactive, double plain_interval_seconds = 10.0);
  // Redraws the bar (terminal) or prints a line if the interval passed (plain).
  void update(const ProgressSnapshot& s, bool force = false);
  // A message on its own line (the bar is redrawn after it).
  void message(const std::string& text);
  void finish();

 private:
  bool interactive_;
  double plain_interval_;
  std::chrono::steady_clock::time_point last_print_;
  bool bar_drawn_ = false;
};

// The progress line: iteration, share done of the nearer limit, speed, loss, model size,
// elapsed time and the estimate of what is left.
std::string progress_line(const ProgressSnapshot& s);

// "1h02m03s", "4m05s", "12s".
std::string format_duration(double seconds);

}  // namespace splat::cli
