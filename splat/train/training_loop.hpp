#pragma once
// The one training loop of splat-train and splat-eval: it steps a TrainerAdapter until a limit
// (iterations, time budget, interrupt) stops it, keeps training time apart from scoring time,
// scores the test views on a schedule, and turns a divergence into a result. What each command
// does with a step or a score (history, checkpoints, progress, model sizes) is an observer's.
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "splat/train/process_group.hpp"
#include "splat/train/trainer_adapter.hpp"

namespace splat {

// Which clock the time budget reads. splat-train's --max-seconds is wall time (scoring
// included), as its help says; splat-eval's budget is training time (scoring excluded), so
// that scoring more often does not shorten a method's training.
enum class BudgetClock { kWall, kTraining };

struct TrainingLoopOptions {
  int iterations = 0;                 // stop once the trainer has completed this many
  double max_seconds = 0;             // time budget, 0 = none
  BudgetClock budget_clock = BudgetClock::kWall;
  const std::atomic<bool>* interrupt = nullptr;  // stop when set (Ctrl-C); none = never

  // Scoring points, any of them (none: never scored by the loop):
  // every N iterations, before iteration N's step (why before: train_command.cpp), for
  // N < iterations;
  int score_every_iterations = 0;
  // The iterations one step advances (a batch of views): a point N is due before the step
  // whose iterations hold it.
  int views_per_step = 1;
  // every T seconds of training time, checked before each step;
  double score_every_seconds = 0;
  // once more when training stopped by a limit, unless the last score saw the final model.
  bool score_at_end = false;
  // At most this share of the training time so far goes to the time-scheduled scores (0: no
  // limit): a due score is skipped when it would take the scoring time past that share. Its
  // cost is estimated from the last score's time per view or, before any, from the first
  // view scored alone (kept as part of the score when it goes ahead). The final score is
  // not limited.
  double score_share = 0;
  // The final score (score_at_end) always runs, and keeps its renders (TrainingLoopResult).
  bool keep_final_renders = false;
  const std::vector<DatasetView>* score_views = nullptr;  // what a score evaluates

  double resumed_seconds = 0;  // training time before this loop (a resumed run)
  // The ranks of a data-parallel run (splat/train/process_group.hpp), or null alone. Every
  // rank then stops at the same step: rank 0's clock decides the time budget and its
  // fraction, an interrupt on any rank stops all. Only rank 0 should be given scoring points.
  ProcessGroup* group = nullptr;
  // Seconds on a monotonic clock; the steady clock unless a test drives time itself.
  std::function<double()> clock;
};

// Where the loop stands, as each hook sees it.
struct LoopState {
  int iteration = 0;        // iterations the trainer has completed
  int first_iteration = 0;  // ... when this loop started (non-zero when resumed)
  double train_seconds = 0; // resumed seconds + this loop's wall time − its scoring time
  double wall_seconds = 0;  // this loop's wall time, scoring included
  double score_seconds = 0; // this loop's time spent scoring so far
  double iterations_per_second() const;  // over this loop's training time
};

// What a command does at the loop's events. The time spent in on_score counts as scoring,
// not training.
class TrainingObserver {
 public:
  virtual ~TrainingObserver() = default;
  virtual void on_step(const StepResult& /*step*/, const LoopState& /*state*/) {}
  // Before a score's evaluation (e.g. to say that scoring takes a while now).
  virtual void on_score_start(const LoopState& /*state*/) {}
  // After it: `evaluate_seconds` is the evaluation's own time; `state` is as when scoring began.
  virtual void on_score(const Evaluation& /*evaluation*/, double /*evaluate_seconds*/,
                        const LoopState& /*state*/) {}
};

// kValidation: the trainer ended training itself (TrainerAdapter::finished).
enum class StopReason { kIterations, kTime, kInterrupt, kDiverged, kValidation };
// "iterations" | "time" | "interrupt" | "diverged" | "validation"
const char* stop_reason_name(StopReason reason);

struct Divergence {
  int iteration = 0;
  std::string group;    // the parameter group (or "loss") that went non-finite
  std::string message;  // TrainingDiverged's: "training diverged at iteration N: non-finite G"
};

struct TrainingLoopResult {
  StopReason stopped_by = StopReason::kIterations;
  std::optional<Divergence> diverged;  // with kDiverged
  double train_seconds = 0;            // when training stopped (a final score not counted)
  double score_seconds = 0;            // all scoring, the final score included
  double final_score_seconds = 0;      // the final score's own
  int skipped_scores = 0;              // time-scheduled scores the score share left out
  std::vector<Image> final_renders;    // [score view], with keep_final_renders
};

// Steps `trainer` until a limit of `options` stops it, then checks every parameter finite; a
// TrainingDiverged from either becomes kDiverged (the trainer keeps its last good model).
// Other exceptions (from the trainer or the observer) propagate.
TrainingLoopResult run_training_loop(TrainerAdapter& trainer, const TrainingLoopOptions& options,
                                     TrainingObserver& observer);

}  // namespace splat
