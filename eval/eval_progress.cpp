#include "eval_progress.hpp"

#include <algorithm>
#include <cstdio>

#include "progress_reporter.hpp"  // format_duration

namespace splat::cli {

namespace {
constexpr double kIntervalSeconds = 5.0;
}

EvalProgress::EvalProgress(bool quiet, int runs, double budget, int scores_per_run)
    : quiet_(quiet), runs_(runs), budget_(budget), scores_per_run_(scores_per_run) {}

void EvalProgress::start_run(int index, const std::string& label) {
  run_ = index;
  label_ = label;
}

void EvalProgress::score_done(double seconds) {
  score_seconds_ += seconds;
  ++scores_;
}

void EvalProgress::report(const std::string& stage, double train_seconds, int iteration, bool force) {
  if (quiet_) return;
  if (!force && printed_ && std::chrono::duration<double>(Clock::now() - last_).count() < kIntervalSeconds)
    return;
  printed_ = true;
  last_ = Clock::now();
  const double training_left = budget_ * (runs_ - run_) - std::min(train_seconds, budget_);
  const double per_score = scores_ > 0 ? score_seconds_ / scores_ : 0;
  const int scores_left = std::max(0, scores_per_run_ * runs_ - scores_);
  const double eta = std::max(0.0, training_left) + per_score * scores_left;
  std::printf("[%s %d/%d] %s: %.1f of %.1f s trained, iteration %d, ETA %s\n", label_.c_str(), run_ + 1,
              runs_, stage.c_str(), train_seconds, budget_, iteration, format_duration(eta).c_str());
  std::fflush(stdout);
}

void EvalProgress::message(const std::string& text) {
  if (quiet_) return;
  std::printf("%s\n", text.c_str());
  std::fflush(stdout);
}

}  // namespace splat::cli
