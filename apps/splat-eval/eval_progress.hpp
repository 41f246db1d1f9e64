#pragma once
// Progress for a whole splat-eval run, over all its training runs: which run, which stage,
// and an ETA. Training time is known in advance (the budgets); scoring during training is at
// most the score share of it (method_run.hpp), and each run ends with one full score of the
// test views, estimated from the scores measured so far (before any, at a tenth of a budget).
#include <chrono>
#include <string>

namespace splat::cli {

class EvalProgress {
 public:
  // `runs` training runs, each of `budget` seconds of training, scoring during training at
  // most `score_share` of it (0: not scored during training), and ending with a score of
  // `test_views` views.
  EvalProgress(bool quiet, int runs, double budget, double score_share, int test_views);

  // The run starting now (0-based) and its label, e.g. "splat" or "views 8 / nerf".
  void start_run(int index, const std::string& label);
  // A score of `views` views took `seconds`.
  void score_done(double seconds, int views);
  // Prints at most every few seconds unless `force`.
  void report(const std::string& stage, double train_seconds, int iteration, bool force = false);
  void message(const std::string& text);
  // The seconds left: training, its scoring share, and the final scores of this run and the
  // ones after it. What report() prints.
  double eta_seconds(double train_seconds) const;

 private:
  using Clock = std::chrono::steady_clock;
  bool quiet_;
  int runs_;
  double budget_, score_share_;
  int test_views_;
  int run_ = 0;
  double score_seconds_ = 0;
  int scored_views_ = 0;
  std::string label_;
  bool printed_ = false;
  Clock::time_point last_;
};

}  // namespace splat::cli
