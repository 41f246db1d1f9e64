// The training loop of splat-train and splat-eval over a fake trainer on a fake clock: a step
// takes one second, an evaluation ten, so every stop, score and second is exact.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "splat/train/training_loop.hpp"

namespace splat {
namespace {

class FakeTrainer final : public TrainerAdapter {
 public:
  explicit FakeTrainer(double& clock) : clock_(clock) {}
  double step_seconds = 1, evaluate_seconds = 10;
  double seconds_per_view = 0;           // when set, an evaluation takes this per view instead
  std::optional<int> diverge_at;         // the step that throws TrainingDiverged
  bool nonfinite_after_steps = false;    // what only the final check sees
  std::optional<int> finished_at;        // the iteration after which the trainer is finished
  std::vector<int> evaluated_at;         // the iteration of each evaluation
  std::vector<double> budget_fractions;  // what the loop said before each step

  StepResult step() override {
    if (diverge_at && iteration_ + 1 == *diverge_at) throw TrainingDiverged(*diverge_at, "means");
    clock_ += step_seconds;
    ++iteration_;
    return {};
  }
  Evaluation evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders) override {
    clock_ += seconds_per_view > 0 ? seconds_per_view * double(views.size()) : evaluate_seconds;
    evaluated_at.push_back(iteration_);
    evaluated_views.push_back(int(views.size()));
    if (renders) renders->assign(views.size(), Image(1, 1, 3));
    Evaluation e;
    e.psnr = iteration_;
    e.views = int(views.size());
    return e;
  }
  std::vector<int> evaluated_views;  // how many views each evaluation scored
  int iteration() const override { return iteration_; }
  bool finished() const override { return finished_at && iteration_ >= *finished_at; }
  void set_time_budget_fraction(double fraction) override { budget_fractions.push_back(fraction); }
  void check_parameters_finite() const override {
    if (nonfinite_after_steps) throw TrainingDiverged(iteration_, "sh_coefficients");
  }

  std::string method() const override { return "fake"; }
  RunSchedule schedule() const override { return {}; }
  std::size_t num_gaussians() const override { return 0; }
  std::size_t num_params() const override { return 0; }
  std::string model_size() const override { return ""; }
  void save_checkpoint(const std::filesystem::path&) const override {}
  void load_checkpoint(const std::filesystem::path&, const GivenSettings&) override {}
  std::string model_file_name() const override { return "model.fake"; }
  void write_model(const std::filesystem::path&) const override {}
  void write_last_good_model(const std::filesystem::path&) const override {}
  nlohmann::json config_json() const override { return {}; }
  void add_metrics(nlohmann::json&) const override {}

 private:
  double& clock_;
  int iteration_ = 0;
};

struct Score {
  int iteration;
  double train_seconds, evaluate_seconds;
};

class RecordingObserver final : public TrainingObserver {
 public:
  std::vector<LoopState> steps;
  std::vector<Score> scores;
  int starts = 0;
  std::optional<int> interrupt_at;
  std::atomic<bool> interrupt{false};

  void on_step(const StepResult&, const LoopState& state) override {
    steps.push_back(state);
    if (interrupt_at && state.iteration == *interrupt_at) interrupt = true;
  }
  void on_score_start(const LoopState&) override { ++starts; }
  void on_score(const Evaluation& e, double evaluate_seconds, const LoopState& state) override {
    EXPECT_EQ(e.psnr, state.iteration);  // the evaluation of the model the state describes
    scores.push_back({state.iteration, state.train_seconds, evaluate_seconds});
  }
};

class TrainingLoop : public ::testing::Test {
 protected:
  TrainingLoop() {
    options.clock = [this] { return clock; };
    options.score_views = &views;
  }
  TrainingLoopResult run() { return run_training_loop(trainer, options, observer); }

  double clock = 1000;  // any origin
  std::vector<DatasetView> views;
  FakeTrainer trainer{clock};
  RecordingObserver observer;
  TrainingLoopOptions options;
};

TEST_F(TrainingLoop, StopsAtTheIterationLimit) {
  options.iterations = 5;
  const auto result = run();
  EXPECT_EQ(result.stopped_by, StopReason::kIterations);
  EXPECT_STREQ(stop_reason_name(result.stopped_by), "iterations");
  EXPECT_EQ(trainer.iteration(), 5);
  ASSERT_EQ(observer.steps.size(), 5u);
  EXPECT_EQ(observer.steps.back().iteration, 5);
  EXPECT_DOUBLE_EQ(result.train_seconds, 5.0);
  EXPECT_TRUE(observer.scores.empty());
}

TEST_F(TrainingLoop, StopsAtTheTimeBudgetOnceItIsReached) {
  options.iterations = 100;
  options.max_seconds = 3.5;
  options.budget_clock = BudgetClock::kTraining;
  const auto result = run();
  EXPECT_EQ(result.stopped_by, StopReason::kTime);
  EXPECT_EQ(trainer.iteration(), 4);  // 3 s < 3.5 s: one more step, which overruns it
  EXPECT_DOUBLE_EQ(result.train_seconds, 4.0);
}

TEST_F(TrainingLoop, TellsTheTrainerHowMuchOfItsBudgetIsSpent) {
  options.iterations = 100;
  options.max_seconds = 4;
  options.budget_clock = BudgetClock::kTraining;
  run();
  EXPECT_EQ(trainer.budget_fractions, (std::vector<double>{0.0, 0.25, 0.5, 0.75}));
  FakeTrainer unbudgeted(clock);
  options.max_seconds = 0;
  options.iterations = 3;
  run_training_loop(unbudgeted, options, observer);
  EXPECT_TRUE(unbudgeted.budget_fractions.empty()) << "no budget, nothing to follow";
}

TEST_F(TrainingLoop, WallClockBudgetCountsScoringTrainingClockBudgetDoesNot) {
  options.iterations = 100;
  options.max_seconds = 15;
  options.score_every_iterations = 2;  // a 10 s score before every second step
  options.budget_clock = BudgetClock::kWall;
  auto result = run();
  EXPECT_EQ(result.stopped_by, StopReason::kTime);
  // Scores before steps 2 and 4 (at iterations 1 and 3): 13 s of wall time after 3 steps,
  // 24 s after the score and the fourth.
  EXPECT_EQ(trainer.iteration(), 4);
  EXPECT_DOUBLE_EQ(result.train_seconds, 4.0);
  EXPECT_DOUBLE_EQ(result.score_seconds, 20.0);

  FakeTrainer fresh(clock);
  RecordingObserver observer2;
  options.budget_clock = BudgetClock::kTraining;
  result = run_training_loop(fresh, options, observer2);
  EXPECT_EQ(result.stopped_by, StopReason::kTime);
  EXPECT_EQ(fresh.iteration(), 15);
  EXPECT_DOUBLE_EQ(result.train_seconds, 15.0);
}

TEST_F(TrainingLoop, ScoresEveryNthIterationBeforeThatIterationsStep) {
  options.iterations = 10;
  options.score_every_iterations = 4;
  const auto result = run();
  // Before steps 4 and 8, i.e. after 3 and 7 completed iterations; not before step 12 (past
  // the end) and not at the end (not asked for).
  EXPECT_EQ(trainer.evaluated_at, (std::vector<int>{3, 7}));
  ASSERT_EQ(observer.scores.size(), 2u);
  EXPECT_EQ(observer.starts, 2);
  EXPECT_DOUBLE_EQ(observer.scores[1].train_seconds, 7.0);
  EXPECT_DOUBLE_EQ(observer.scores[1].evaluate_seconds, 10.0);
  EXPECT_EQ(trainer.iteration(), 10);
  EXPECT_DOUBLE_EQ(result.score_seconds, 20.0);
}

TEST_F(TrainingLoop, ScoresEveryTSecondsOfTrainingTimeAndOnceAtTheEnd) {
  options.iterations = 6;
  options.score_every_seconds = 2.5;
  options.score_at_end = true;
  const auto result = run();
  // Due at 2.5 s (checked at 3 s) and 5 s, then the final model at iteration 6.
  EXPECT_EQ(trainer.evaluated_at, (std::vector<int>{3, 5, 6}));
  ASSERT_EQ(observer.scores.size(), 3u);
  EXPECT_DOUBLE_EQ(observer.scores[0].train_seconds, 3.0);
  EXPECT_DOUBLE_EQ(observer.scores[1].train_seconds, 5.0);
  EXPECT_DOUBLE_EQ(observer.scores[2].train_seconds, 6.0);
  EXPECT_DOUBLE_EQ(result.score_seconds, 30.0);
}

TEST_F(TrainingLoop, ScoringTimeIsExcludedFromTrainingSeconds) {
  options.iterations = 8;
  options.score_every_iterations = 2;
  const auto result = run();
  // 8 steps of 1 s and 3 scores of 10 s (before steps 2, 4, 6): 38 s of wall time, 8 s of
  // training.
  EXPECT_DOUBLE_EQ(result.train_seconds, 8.0);
  EXPECT_DOUBLE_EQ(result.score_seconds, 30.0);
  for (const LoopState& s : observer.steps) {
    EXPECT_DOUBLE_EQ(s.train_seconds, s.iteration);
    EXPECT_DOUBLE_EQ(s.wall_seconds, s.train_seconds + s.score_seconds);
    EXPECT_DOUBLE_EQ(s.iterations_per_second(), 1.0);
  }
}

TEST_F(TrainingLoop, ResumedTimeCountsAsTrainingAndKeepsTheScoringGrid) {
  options.iterations = 5;
  options.resumed_seconds = 100;
  options.score_every_seconds = 30;  // the next point after 100 s is 120 s: not reached
  const auto result = run();
  EXPECT_TRUE(trainer.evaluated_at.empty());
  EXPECT_DOUBLE_EQ(result.train_seconds, 105.0);
}

TEST_F(TrainingLoop, DivergenceIsReportedWithIterationAndGroup) {
  options.iterations = 10;
  options.score_at_end = true;
  trainer.diverge_at = 4;
  const auto result = run();
  EXPECT_EQ(result.stopped_by, StopReason::kDiverged);
  ASSERT_TRUE(result.diverged);
  EXPECT_EQ(result.diverged->iteration, 4);
  EXPECT_EQ(result.diverged->group, "means");
  EXPECT_NE(result.diverged->message.find("diverged at iteration 4"), std::string::npos);
  EXPECT_EQ(observer.steps.size(), 3u);
  EXPECT_DOUBLE_EQ(result.train_seconds, 3.0);
  EXPECT_TRUE(trainer.evaluated_at.empty());  // a diverged model is not scored
}

TEST_F(TrainingLoop, TheFinalCheckReportsWhatTheStepsMissed) {
  options.iterations = 3;
  options.score_at_end = true;
  trainer.nonfinite_after_steps = true;
  const auto result = run();
  EXPECT_EQ(result.stopped_by, StopReason::kDiverged);
  ASSERT_TRUE(result.diverged);
  EXPECT_EQ(result.diverged->iteration, 3);
  EXPECT_EQ(result.diverged->group, "sh_coefficients");
  EXPECT_TRUE(trainer.evaluated_at.empty());
}

TEST_F(TrainingLoop, InterruptStopsBeforeTheNextStepWithoutAFinalScore) {
  options.iterations = 10;
  options.score_at_end = true;
  options.interrupt = &observer.interrupt;
  observer.interrupt_at = 2;
  const auto result = run();
  EXPECT_EQ(result.stopped_by, StopReason::kInterrupt);
  EXPECT_EQ(trainer.iteration(), 2);
  EXPECT_TRUE(trainer.evaluated_at.empty());
}

TEST_F(TrainingLoop, AFinishedTrainerStopsTheLoopBeforeAnotherStepAndIsScoredOnce) {
  trainer.finished_at = 7;
  options.iterations = 100;
  options.score_at_end = true;
  const TrainingLoopResult result = run();
  EXPECT_EQ(result.stopped_by, StopReason::kValidation);
  EXPECT_STREQ(stop_reason_name(result.stopped_by), "validation");
  EXPECT_EQ(trainer.iteration(), 7);
  EXPECT_EQ(trainer.evaluated_at, std::vector<int>{7});
}

TEST_F(TrainingLoop, ScoringWithoutViewsIsRefused) {
  options.iterations = 1;
  options.score_at_end = true;
  options.score_views = nullptr;
  EXPECT_THROW(run(), ArgumentError);
}


// Time-scheduled scores are taken only while scoring stays within its share of the training
// time: each costs 4 s (four views at 1 s), the first estimated from one view scored alone.
// 100 s of training scored every `every` seconds within a tenth of it; four views at 1 s each.
class ScoreShare : public TrainingLoop {
 protected:
  void set_up(double every) {
    views.resize(4);
    trainer.seconds_per_view = 1;
    options.iterations = 1000;
    options.max_seconds = 100;
    options.budget_clock = BudgetClock::kTraining;
    options.score_every_seconds = every;
    options.score_share = 0.1;
  }
};

TEST_F(ScoreShare, ScoresStayWithinTheirShareOfTrainingTime) {
  set_up(10);
  options.score_at_end = true;
  const auto result = run();
  // At 10 s the probe (1 s) plus the other three views would take 4 s of an allowed 1 s:
  // skipped, the probe counted. Then 1 + 4 s fits at 50 s (5 s allowed), 5 + 4 at 90 s.
  ASSERT_EQ(observer.scores.size(), 3u);
  EXPECT_DOUBLE_EQ(observer.scores[0].train_seconds, 50.0);
  EXPECT_DOUBLE_EQ(observer.scores[1].train_seconds, 90.0);
  EXPECT_DOUBLE_EQ(observer.scores[2].train_seconds, 100.0);  // the final score, not limited
  EXPECT_EQ(trainer.evaluated_views, (std::vector<int>{1, 4, 4, 4}));
  EXPECT_EQ(result.skipped_scores, 7);  // 10, 20, 30, 40, 60, 70, 80 s
  EXPECT_DOUBLE_EQ(result.score_seconds, 13.0);
  EXPECT_DOUBLE_EQ(result.final_score_seconds, 4.0);
  EXPECT_LE(result.score_seconds - result.final_score_seconds, 0.1 * result.train_seconds);
}

// A probe that fits goes on with the other views: one score of all of them.
TEST_F(ScoreShare, AnAffordableProbeBecomesPartOfTheScore) {
  set_up(60);
  run();
  EXPECT_EQ(trainer.evaluated_views, (std::vector<int>{1, 3}));
  ASSERT_EQ(observer.scores.size(), 1u);
  EXPECT_DOUBLE_EQ(observer.scores[0].evaluate_seconds, 4.0);
}

TEST_F(TrainingLoop, KeepsTheFinalScoresRendersEvenWhenTheModelWasJustScored) {
  views.resize(3);
  options.iterations = 10;
  options.score_every_iterations = 5;
  options.score_at_end = true;
  options.keep_final_renders = true;
  const auto result = run();
  EXPECT_EQ(trainer.evaluated_at, (std::vector<int>{4, 10}));
  EXPECT_EQ(result.final_renders.size(), 3u);
  EXPECT_DOUBLE_EQ(result.final_score_seconds, 10.0);
}

}  // namespace
}  // namespace splat
