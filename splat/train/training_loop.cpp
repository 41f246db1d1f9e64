#include "splat/train/training_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <span>

#include "splat/optim/step_events.hpp"

namespace splat {

namespace {

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

class Loop {
 public:
  Loop(TrainerAdapter& trainer, const TrainingLoopOptions& options, TrainingObserver& observer)
      : trainer_(trainer), options_(options), observer_(observer),
        clock_(options.clock ? options.clock : steady_seconds), start_(clock_()) {
    state_.first_iteration = trainer.iteration();
    // The first time point after the resumed time, so a resumed run keeps the grid.
    if (options.score_every_seconds > 0)
      next_score_at_ = options.score_every_seconds *
                       (std::floor(options.resumed_seconds / options.score_every_seconds) + 1);
  }

  TrainingLoopResult run() {
    TrainingLoopResult result;
    try {
      result.stopped_by = train();
      result.train_seconds = now().train_seconds;
      trainer_.check_parameters_finite();  // the groups a step checks only now and then
    } catch (const TrainingDiverged& diverged) {
      result.stopped_by = StopReason::kDiverged;
      result.diverged = Divergence{diverged.iteration(), diverged.group(), diverged.what()};
      result.train_seconds = now().train_seconds;
      result.score_seconds = state_.score_seconds;
      return result;
    }
    if (options_.score_at_end && result.stopped_by != StopReason::kInterrupt &&
        (options_.keep_final_renders || last_scored_ != trainer_.iteration())) {
      const double before = state_.score_seconds;
      score(*options_.score_views, options_.keep_final_renders ? &result.final_renders : nullptr);
      result.final_score_seconds = state_.score_seconds - before;
    }
    result.score_seconds = state_.score_seconds;
    result.skipped_scores = skipped_scores_;
    return result;
  }

 private:
  StopReason train() {
    for (;;) {
      const LoopState s = now();
      if (s.iteration >= options_.iterations) return StopReason::kIterations;
      if (trainer_.finished()) return StopReason::kValidation;  // the same on every rank
      bool interrupted = options_.interrupt && options_.interrupt->load();
      double spent = options_.budget_clock == BudgetClock::kWall ? s.wall_seconds : s.train_seconds;
      if (options_.group) {  // every rank takes the same decision: rank 0's time, anyone's interrupt
        interrupted = options_.group->any(interrupted);
        options_.group->broadcast(std::span<double>(&spent, 1));
      }
      if (interrupted) return StopReason::kInterrupt;
      if (options_.max_seconds > 0 && spent >= options_.max_seconds) return StopReason::kTime;
      if (options_.max_seconds > 0) trainer_.set_time_budget_fraction(spent / options_.max_seconds);
      if (score_due(s)) {
        scheduled_score(s);
        // One score however far behind the grid fell (a slow step, a long score).
        while (options_.score_every_seconds > 0 && next_score_at_ <= now().train_seconds)
          next_score_at_ += options_.score_every_seconds;
      }
      const StepResult step = trainer_.step();
      observer_.on_step(step, now());
    }
  }

  bool score_due(const LoopState& s) const {
    const int views = options_.views_per_step;
    const int next = s.iteration + views;  // the last iteration of the next step
    const int every = options_.score_every_iterations;
    if (step_reaches_multiple(next, views, every) && next < options_.iterations) return true;
    return options_.score_every_seconds > 0 && s.train_seconds >= next_score_at_;
  }

  void score(const std::vector<DatasetView>& views, std::vector<Image>* renders,
             const std::optional<Evaluation>& probe = std::nullopt, double probe_seconds = 0) {
    const LoopState at = now();
    const double start = clock_();
    observer_.on_score_start(at);
    const double evaluate_start = clock_();
    Evaluation evaluation = trainer_.evaluate(views, renders);
    if (probe) evaluation = merged(*probe, evaluation);
    const double evaluate_seconds = clock_() - evaluate_start + probe_seconds;
    seconds_per_view_ = evaluate_seconds / double(std::max(1, evaluation.views));
    observer_.on_score(evaluation, evaluate_seconds, at);
    state_.score_seconds += clock_() - start;
    last_scored_ = at.iteration;
  }

  // A time-scheduled score, within the score share (score_share's comment).
  void scheduled_score(const LoopState& s) {
    const std::vector<DatasetView>& views = *options_.score_views;
    if (options_.score_share <= 0 || views.empty()) return score(views, nullptr);
    const double start = clock_();
    std::optional<Evaluation> probe;
    if (seconds_per_view_ == 0) {
      probe = trainer_.evaluate({views.front()}, nullptr);
      seconds_per_view_ = clock_() - start;
    }
    const double probe_seconds = clock_() - start;
    const double rest = seconds_per_view_ * double(views.size() - (probe ? 1 : 0));
    if (state_.score_seconds + probe_seconds + rest > options_.score_share * s.train_seconds) {
      state_.score_seconds += probe_seconds;  // what the probe cost is scoring time too
      ++skipped_scores_;
      return;
    }
    state_.score_seconds += probe_seconds;
    if (probe) return score(std::vector<DatasetView>(views.begin() + 1, views.end()), nullptr, probe, probe_seconds);
    score(views, nullptr);
  }

  const LoopState& now() {
    state_.iteration = trainer_.iteration();
    state_.wall_seconds = clock_() - start_;
    state_.train_seconds = options_.resumed_seconds + state_.wall_seconds - state_.score_seconds;
    return state_;
  }

  TrainerAdapter& trainer_;
  const TrainingLoopOptions& options_;
  TrainingObserver& observer_;
  std::function<double()> clock_;
  double start_;
  LoopState state_;
  double next_score_at_ = 0;
  int last_scored_ = -1;
  double seconds_per_view_ = 0;  // of the last score: the next one's estimate
  int skipped_scores_ = 0;
};

}  // namespace

double LoopState::iterations_per_second() const {
  return (iteration - first_iteration) / std::max(1e-9, wall_seconds - score_seconds);
}

const char* stop_reason_name(StopReason reason) {
  switch (reason) {
    case StopReason::kIterations: return "iterations";
    case StopReason::kTime: return "time";
    case StopReason::kInterrupt: return "interrupt";
    case StopReason::kDiverged: return "diverged";
    case StopReason::kValidation: return "validation";
  }
  return "?";
}

TrainingLoopResult run_training_loop(TrainerAdapter& trainer, const TrainingLoopOptions& options,
                                     TrainingObserver& observer) {
  if (options.score_views == nullptr &&
      (options.score_every_iterations > 0 || options.score_every_seconds > 0 || options.score_at_end))
    throw ArgumentError("training loop: scoring is scheduled but no views are given to score");
  return Loop(trainer, options, observer).run();
}

}  // namespace splat
