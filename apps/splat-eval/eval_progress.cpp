#include "apps/splat-eval/eval_progress.hpp"

#include <algorithm>
#include <cstdio>

#include "apps/common/progress_reporter.hpp"  // format_duration

namespace splat::cli {

namespace {
constexpr double kIntervalSeconds = 5.0;
// Before any score is measured, a final score is guessed at this share of a budget.
constexpr double kFinalScoreGuessShare = 0.1;
}

EvalProgress::EvalProgress(bool quiet, int runs, double budget, double score_share, int test_views)
    : quiet_(quiet), runs_(runs), budget_(budget), score_share_(score_share), test_views_(test_views) {}

void EvalProgress::start_run(int index, const std::string& label) {
  run_ = index;
  label_ = label;
}

void EvalProgress::score_done(double seconds, int views) {
  score_seconds_ += seconds;
  scored_views_ += views;
}

double EvalProgress::eta_seconds(double train_seconds) const {
  const double training_left = std::max(0.0, budget_ * (runs_ - run_) - std::min(train_seconds, budget_));
  const double final_score = scored_views_ > 0 ? score_seconds_ / scored_views_ * test_views_
                                               : kFinalScoreGuessShare * budget_;
  return training_left * (1 + score_share_) + final_score * (runs_ - run_);
}

void EvalProgress::report(const std::string& stage, double train_seconds, int iteration, bool force) {
  if (quiet_) return;
  if (!force && printed_ && std::chrono::duration<double>(Clock::now() - last_).count() < kIntervalSeconds)
    return;
  printed_ = true;
  last_ = Clock::now();
  std::printf("[%s %d/%d] %s: %.1f of %.1f s trained, iteration %d, ETA %s\n", label_.c_str(), run_ + 1,
              runs_, stage.c_str(), train_seconds, budget_, iteration,
              format_duration(eta_seconds(train_seconds)).c_str());
  std::fflush(stdout);
}

void EvalProgress::message(const std::string& text) {
  if (quiet_) return;
  std::printf("%s\n", text.c_str());
  std::fflush(stdout);
}

}  // namespace splat::cli
