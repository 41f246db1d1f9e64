#pragma once
// Progress for a whole splat-eval run, over all its training runs: which run, which stage,
// and an ETA. Training time is known in advance (the budgets); scoring time is estimated
// from the scores done so far.
#include <chrono>
#include <string>

namespace splat::cli {

class EvalProgress {
 public:
  // `runs` training runs, each of `budget` seconds and scored `scores_per_run` times.
  EvalProgress(bool quiet, int runs, double budget, int scores_per_run);

  // The run starting now (0-based) and its label, e.g. "splat" or "views 8 / nerf".
  void start_run(int index, const std::string& label);
  void score_done(double seconds);
  // Prints at most every few seconds unless `force`.
  void report(const std::string& stage, double train_seconds, int iteration, bool force = false);
  void message(const std::string& text);

 private:
  using Clock = std::chrono::steady_clock;
  bool quiet_;
  int runs_;
  double budget_;
  int scores_per_run_;
  int run_ = 0, scores_ = 0;
  double score_seconds_ = 0;
  std::string label_;
  bool printed_ = false;
  Clock::time_point last_;
};

}  // namespace splat::cli
