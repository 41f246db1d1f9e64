#pragma once
// Model selection on a real capture without touching its test views. On a capture the late
// part of training can learn floaters that explain the training photos and spoil every other
// view (issue 40: wild_statue peaks after 500 iterations and loses 1 dB by the end, as the
// official code does). A few training views are held out as a validation set while the model
// grows; they are scored every `interval` iterations (before the step that holds the
// multiple, after `interval` − 1 of them, as the test views are) and the best-scoring model is
// kept. When the schedule reaches `decide_at` (half-way through growth in the compact
// recipe) the holdout decides once:
//   - validation has held (the median of its last three scores within `fall_db` of the best
//     median of three consecutive ones): the views rejoin training and the run goes on as it
//     would have;
//   - it has fallen: the best-scoring model is restored and training stops there
//     ("validation").
// Medians of three rather than single scores, so that neither a single dip (real_cup dips
// 0.4 dB for 1,000 iterations mid-run and rises 1.2 dB after) nor a single high score
// (real_thermos wanders ±0.3 dB between neighbouring scores after its resolution warm-up) is
// read as a fall.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "splat/data/dataset.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/train/validation_settings.hpp"

namespace splat {

class ValidationHoldout {
 public:
  enum class Decision { kWait, kRejoin, kRestore };

  ValidationHoldout() = default;
  ValidationHoldout(const Dataset& dataset, const ValidationSettings& settings);

  // Whether the views are still held out (off, or decided: none are).
  bool active() const { return !train_indices_.empty() && decision_ == Decision::kWait; }
  // Whether training view `train_view` is held out now.
  bool holds_out(std::size_t train_view) const;
  const std::vector<DatasetView>& views() const { return views_; }
  // Whether the step that ends at `last_iteration` (a batch of `batch` views) holds a scoring
  // point (the trainer scores before that step).
  bool due(int last_iteration, int batch) const;

  // A validation score of the model as it is after iteration `iteration`: kept as the best
  // model when it beats every earlier one. Then, once `schedule_fraction` reaches decide_at,
  // the decision (kWait before): the holdout is inactive after it.
  Decision record(int iteration, double psnr, const GaussianModel& model, double schedule_fraction);

  // Whether the decision was to restore the best model (training ends there).
  bool restored() const { return decision_ == Decision::kRestore; }
  // The model of the best score (valid until the decision releases it).
  const GaussianModel& best_model() const { return best_model_; }

  // Why training ended, for the user, once the holdout restored its best model: the best
  // score, the last one and the model kept (empty otherwise).
  std::string restore_summary() const;
  // For metrics.json: the held-out views, every score, the best and the decision.
  nlohmann::json metrics() const;
  // The checkpoint's part: scalar state in the header, and while undecided the best model,
  // whose arrays follow the others (checkpoint_model(): null when there is none to save).
  nlohmann::json checkpoint_state() const;
  const GaussianModel* checkpoint_model() const { return active() && !scores_.empty() ? &best_model_ : nullptr; }
  GaussianModel* checkpoint_model() { return active() && !scores_.empty() ? &best_model_ : nullptr; }
  // After the header's state was read (then the model's arrays into checkpoint_model(), then
  // checkpoint_model_loaded): ArgumentError if they do not fit. `state` null (a checkpoint
  // from before the holdout): treated as decided, every view trained on.
  void checkpoint_state_loaded(const nlohmann::json& state);
  void checkpoint_model_loaded(int sh_degree);

 private:
  struct Score {
    int iteration;
    double psnr;
  };
  // The first of the highest scores (none before the first).
  std::optional<Score> best() const;
  // The median of the kMedianWidth scores that end at index `last` (of fewer at the start).
  double median_at(std::size_t last) const;
  // How far the median of the last scores is below the best median (≥ 0; scores not empty).
  double fall_db() const;
  static constexpr std::size_t kMedianWidth = 3;

  ValidationSettings settings_;
  std::vector<std::size_t> train_indices_;  // of the held-out views, ascending
  std::vector<DatasetView> views_;
  std::vector<Score> scores_;
  GaussianModel best_model_;  // the model of best(), kept while undecided
  std::optional<int> decided_at_;
  Decision decision_ = Decision::kWait;
};

}  // namespace splat
