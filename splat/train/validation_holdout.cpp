#include "splat/train/validation_holdout.hpp"

#include <algorithm>
#include <cstdio>

#include "splat/core/error.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/train/validation_views.hpp"

namespace splat {

ValidationHoldout::ValidationHoldout(const Dataset& dataset, const ValidationSettings& settings)
    : settings_(settings) {
  if (settings.every <= 0 || !dataset.points) return;
  train_indices_ = choose_validation_views(dataset.train, *dataset.points, settings.every);
  // One view is too few to tell a fall from that view's own noise.
  if (train_indices_.size() < 2) {
    train_indices_.clear();
    return;
  }
  for (std::size_t i : train_indices_) views_.push_back(dataset.train[i]);
}

std::optional<ValidationHoldout::Score> ValidationHoldout::best() const {
  if (scores_.empty()) return std::nullopt;
  return *std::max_element(scores_.begin(), scores_.end(),
                           [](const Score& a, const Score& b) { return a.psnr < b.psnr; });
}

double ValidationHoldout::median_at(std::size_t last) const {
  const std::size_t first = last + 1 >= kMedianWidth ? last + 1 - kMedianWidth : 0;
  std::vector<double> window;
  for (std::size_t i = first; i <= last; ++i) window.push_back(scores_[i].psnr);
  // The upper median: of two, the better (a dip is not the level).
  std::nth_element(window.begin(), window.begin() + window.size() / 2, window.end());
  return window[window.size() / 2];
}

double ValidationHoldout::fall_db() const {
  double best_median = median_at(0);
  for (std::size_t last = 1; last < scores_.size(); ++last) best_median = std::max(best_median, median_at(last));
  return best_median - median_at(scores_.size() - 1);
}

bool ValidationHoldout::holds_out(std::size_t train_view) const {
  return active() && std::binary_search(train_indices_.begin(), train_indices_.end(), train_view);
}

bool ValidationHoldout::due(int last_iteration, int batch) const {
  return active() && step_reaches_multiple(last_iteration, batch, settings_.interval);
}

ValidationHoldout::Decision ValidationHoldout::record(int iteration, double psnr, const GaussianModel& model,
                                                      double schedule_fraction) {
  if (!active()) return decision_;
  const std::optional<Score> best_before = best();
  scores_.push_back({iteration, psnr});
  if (!best_before || psnr > best_before->psnr) best_model_ = model;
  if (schedule_fraction < settings_.decide_at) return Decision::kWait;
  decision_ = fall_db() > settings_.fall_db ? Decision::kRestore : Decision::kRejoin;
  decided_at_ = iteration;
  // Restoring hands the best model over (the trainer copies it); rejoining has no use for it.
  if (decision_ == Decision::kRejoin) best_model_ = GaussianModel{};
  return decision_;
}

namespace {

const char* decision_name(ValidationHoldout::Decision d) {
  switch (d) {
    case ValidationHoldout::Decision::kWait: return "undecided";
    case ValidationHoldout::Decision::kRejoin: return "rejoined";
    case ValidationHoldout::Decision::kRestore: return "restored";
  }
  return "?";
}

}  // namespace

std::string ValidationHoldout::restore_summary() const {
  const std::optional<Score> best = this->best();
  if (!restored() || !best) return {};
  char line[256];
  std::snprintf(line, sizeof(line),
                "validation: the held-out views fell %.2f dB (the median of their last three scores against "
                "the best such median; the last %.3f dB at iteration %d); training stopped on the model of "
                "iteration %d (%.3f dB)",
                fall_db(), scores_.back().psnr, scores_.back().iteration, best->iteration, best->psnr);
  return line;
}

nlohmann::json ValidationHoldout::metrics() const {
  if (train_indices_.empty()) return nullptr;
  nlohmann::json m;
  m["views"] = nlohmann::json::array();
  for (const DatasetView& v : views_) m["views"].push_back(v.name);
  m["scores"] = nlohmann::json::array();
  for (const Score& s : scores_) m["scores"].push_back({{"iteration", s.iteration}, {"psnr", s.psnr}});
  if (const std::optional<Score> best = this->best()) m["best"] = {{"iteration", best->iteration}, {"psnr", best->psnr}};
  m["decision"] = decision_name(decision_);
  if (decided_at_) m["decided_at_iteration"] = *decided_at_;
  if (decided_at_ && !scores_.empty()) m["fall_measured_db"] = fall_db();
  m["fall_db"] = settings_.fall_db;
  return m;
}

nlohmann::json ValidationHoldout::checkpoint_state() const {
  nlohmann::json j;
  j["active"] = active();
  j["decision"] = int(decision_);
  if (decided_at_) j["decided_at"] = *decided_at_;
  j["scores"] = nlohmann::json::array();
  for (const Score& s : scores_) j["scores"].push_back({s.iteration, s.psnr});
  return j;
}

void ValidationHoldout::checkpoint_state_loaded(const nlohmann::json& state) {
  scores_.clear();
  decided_at_.reset();
  best_model_ = GaussianModel{};
  decision_ = Decision::kRejoin;  // written before the holdout existed: train on every view
  if (state.is_null()) return;
  const bool held_out = state.at("active").get<bool>();
  if (held_out && train_indices_.empty())
    throw ArgumentError("the checkpoint holds validation views out but these settings and data have none");
  const int decision = state.at("decision").get<int>();
  if (decision < 0 || decision > int(Decision::kRestore)) throw ArgumentError("validation decision is corrupt");
  if (held_out && Decision(decision) != Decision::kWait)
    throw ArgumentError("validation state is corrupt: views held out after the decision");
  // Undecided and nothing held out (a run without validation views): every view trains on.
  if (held_out || Decision(decision) != Decision::kWait) decision_ = Decision(decision);
  if (state.contains("decided_at")) decided_at_ = state.at("decided_at").get<int>();
  for (const nlohmann::json& s : state.at("scores")) scores_.push_back({s.at(0).get<int>(), s.at(1).get<double>()});
}

void ValidationHoldout::checkpoint_model_loaded(int sh_degree) {
  best_model_.sh_degree = sh_degree;
  if (checkpoint_model()) best_model_.check_consistent();
}

}  // namespace splat
