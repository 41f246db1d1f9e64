#include "splat/train/nerf_trainer.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <cmath>
#include <optional>
#include <fstream>
#include <span>
#include <sstream>
#include <string>

#include "splat/core/atomic_file.hpp"
#include "splat/core/file_bytes.hpp"
#include "splat/core/json_file.hpp"
#include "splat/core/random.hpp"
#include "splat/core/settings_table.hpp"
#include "splat/nerf/nerf_file.hpp"
#include "splat/optim/lr_schedule.hpp"
#include "splat/train/training_support.hpp"

namespace splat {

namespace {

using training::all_finite;
using training::Clock;
using training::kLastGoodInterval;
using training::ms_since;

constexpr char kCheckpointMagic[8] = {'S', 'P', 'L', 'N', 'R', 'F', 'C', 'K'};
// Version 2 adds the parameter average; a version-1 checkpoint resumes with the average
// restarted at its parameters.
constexpr std::uint32_t kCheckpointVersion = 3;  // 3: the settings follow the random state

void write_floats(std::ostream& out, std::span<const float> v) {
  const std::uint64_t n = v.size();
  out.write(reinterpret_cast<const char*>(&n), sizeof(n));
  out.write(reinterpret_cast<const char*>(v.data()), std::streamsize(n * sizeof(float)));
}

// `what` names the array in the errors ("optimiser state", ...).
void read_floats(std::istream& in, std::span<float> v, const std::filesystem::path& file, const std::string& what) {
  std::uint64_t n = 0;
  in.read(reinterpret_cast<char*>(&n), sizeof(n));
  if (!in || n != v.size()) throw InputError(file, what + " does not match the model");
  in.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(float)));
  if (!in) throw InputError(file, "truncated " + what);
}

FlatAdamSettings adam_settings(const NerfTrainingConfig& config) {
  FlatAdamSettings s;
  s.beta2 = config.adam_beta2;
  s.epsilon = config.adam_epsilon;
  return s;
}

}  // namespace

NerfTrainer::NerfTrainer(const Dataset& dataset, const NerfTrainingConfig& config)
    : dataset_(dataset), config_(validated(config)), model_(config.model, config.seed), averaged_(model_),
      last_good_model_(model_), coarse_adam_(model_.coarse.parameter_count(), adam_settings(config_)),
      fine_adam_(model_.fine.parameter_count(), adam_settings(config_)), rng_(config.seed) {
  if (dataset.train.empty()) throw ArgumentError("training needs at least one training view");
  for (NerfMlp* mlp : {&model_.coarse, &model_.fine}) {
    const NerfLayerShape& density = mlp->layers()[std::size_t(mlp->density_layer())];
    mlp->parameters()[density.offset + std::size_t(density.in)] = config_.density_bias_init;
  }
  averaged_ = model_;
  last_good_model_ = model_;
}

double NerfTrainer::schedule_progress() const {
  if (config_.schedule_follows_budget && config_.max_seconds > 0) return std::min(1.0, time_budget_fraction_);
  return std::min(1.0, double(iteration_) / double(std::max(1, config_.lr_decay_iterations)));
}

float NerfTrainer::learning_rate() const {
  // Log-linear from lr_init to lr_final over the run, as the paper's exponential decay.
  return float(ExponentialLrSchedule{config_.lr_init, config_.lr_final, 1}.at_fraction(schedule_progress()));
}

void NerfTrainer::update_occupancy() {
  // A cell may hold density if either network sees some there: the coarse network places
  // the samples the fine one refines.
  const OccupancyGrid::DensityFunction density = [&](std::span<const glm::vec3> points,
                                                     std::span<float> sigmas) {
    const std::size_t n = points.size();
    density_positions_.resize(3 * n);
    density_sigma_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) density_positions_[3 * i + a] = points[i][a];
    density_max_.resize(n);
    model_.coarse.forward_density(density_positions_, density_max_, coarse_density_context_);
    model_.fine.forward_density(density_positions_, density_sigma_, fine_density_context_);
    for (std::size_t i = 0; i < n; ++i) sigmas[i] = std::max(density_max_[i], density_sigma_[i]);
  };
  OccupancyUpdateOptions options;
  options.cells = config_.occupancy_cells_per_update;
  model_.grid.update(density, rng_, options);
}

void NerfTrainer::update_average() {
  if (config_.parameter_average_decay <= 0) return;
  // The average starts halfway through the rate's decay (until then it is the iterate): at
  // a high rate the model still improves quickly and an average would lag behind it
  // (thin_structures, 1,500 iterations, the average from the start: −0.20 dB).
  const float d = schedule_progress() < kAverageFromProgress ? 0.0f : config_.parameter_average_decay;
  const auto move = [d](std::span<const float> live, std::span<float> average) {
    for (std::size_t i = 0; i < live.size(); ++i) average[i] = d * average[i] + (1 - d) * live[i];
  };
  move(model_.coarse.parameters(), averaged_.coarse.parameters());
  move(model_.fine.parameters(), averaged_.fine.parameters());
}

StepResult NerfTrainer::step() {
  const int iteration = iteration_ + 1;
  StepResult result;
  auto start = Clock::now();
  // Random rays across all training images: a view, then a pixel, from the trainer's RNG.
  const std::size_t batch = std::size_t(config_.rays_per_batch);
  rays_.resize(batch);
  targets_.resize(3 * batch);
  if (config_.random_background) ray_backgrounds_.resize(3 * batch);
  // Pixels a view's mask leaves out are drawn again (a few times at most: a mask that keeps
  // almost nothing must not stall the step), so they are never trained on.
  constexpr int kMaxDraws = 16;
  for (std::size_t r = 0; r < batch; ++r) {
    const DatasetView* drawn = nullptr;
    int x = 0, y = 0;
    for (int draw = 1;; ++draw) {
      drawn = &dataset_.train[rng_() % dataset_.train.size()];
      x = int(rng_() % std::uint32_t(drawn->image.width));
      y = int(rng_() % std::uint32_t(drawn->image.height));
      if (drawn->mask.empty() || drawn->mask.at(x, y, 0) >= 0.5f || draw == kMaxDraws) break;
    }
    const DatasetView& view = *drawn;
    rays_[r] = camera_ray(view.camera, float(x), float(y));
    for (int c = 0; c < 3; ++c) targets_[3 * r + c] = view.image.at(x, y, c);
    if (!config_.random_background) continue;
    float* background = &ray_backgrounds_[3 * r];
    std::copy(config_.background, config_.background + 3, background);
    if (view.alpha.empty()) continue;  // an opaque photo: no ray sees what is behind it
    // The photo onto the ray's own colour: image + (1 − α)(new − old background).
    const float transparency = 1.0f - view.alpha.at(x, y, 0);
    for (int c = 0; c < 3; ++c) {
      background[c] = uniform01(rng_);
      targets_[3 * r + c] += transparency * (background[c] - config_.background[c]);
    }
  }
  if (config_.random_background)
    renderer_.forward(model_, rays_, RayBackgrounds(std::span<const float>(ray_backgrounds_)), /*jitter=*/true,
                      rng_, forward_);
  else
    renderer_.forward(model_, rays_, config_.background, /*jitter=*/true, rng_, forward_);
  result.timings.forward = ms_since(start);
  ++sample_counts_.steps;
  sample_counts_.coarse += forward_.coarse_sample_count();
  sample_counts_.fine += forward_.fine_sample_count();

  start = Clock::now();
  // L = MSE(coarse) + MSE(fine) over the batch's rays and channels (the paper's loss).
  const auto& coarse = forward_.coarse_color();
  const auto& fine = forward_.fine_color();
  v_coarse_.resize(3 * batch);
  v_fine_.resize(3 * batch);
  double coarse_sse = 0, fine_sse = 0;
  const float scale = 2.0f / float(3 * batch);
  for (std::size_t i = 0; i < 3 * batch; ++i) {
    const float dc = coarse[i] - targets_[i], df = fine[i] - targets_[i];
    coarse_sse += double(dc) * dc;
    fine_sse += double(df) * df;
    v_coarse_[i] = scale * dc;
    v_fine_[i] = scale * df;
  }
  const double fine_mse = fine_sse / double(3 * batch);
  result.loss = coarse_sse / double(3 * batch) + fine_mse;
  result.l1 = fine_mse;  // the fine pass's MSE (what the test PSNR measures)
  result.timings.loss = ms_since(start);
  if (!std::isfinite(result.loss)) throw TrainingDiverged(iteration, "loss");

  start = Clock::now();
  coarse_grad_.assign(model_.coarse.parameter_count(), 0.0f);
  fine_grad_.assign(model_.fine.parameter_count(), 0.0f);
  renderer_.backward(model_, forward_, v_coarse_, v_fine_, coarse_grad_, fine_grad_);
  result.timings.backward = ms_since(start);

  start = Clock::now();
  const float lr = learning_rate();
  coarse_adam_.step(model_.coarse.parameters(), coarse_grad_, lr);
  fine_adam_.step(model_.fine.parameters(), fine_grad_, lr);
  check_finite(iteration);
  result.timings.optimizer = ms_since(start);

  start = Clock::now();
  if (iteration >= config_.occupancy_warmup && iteration % config_.occupancy_interval == 0) {
    update_occupancy();
    averaged_.grid = model_.grid;  // the average renders through the live grid
  }
  result.timings.densify = ms_since(start);  // the grid update is this method's "densify"
  start = Clock::now();
  update_average();
  if (iteration % kLastGoodInterval == 0) last_good_model_ = model();
  result.timings.optimizer += ms_since(start);
  iteration_ = iteration;
  return result;
}

Image NerfTrainer::render(const Camera& camera) {
  Image image = renderer_.render_image(model(), camera, config_.background, forward_);
  for (float& v : image.data) v = std::clamp(v, 0.0f, 1.0f);
  return image;
}

Evaluation NerfTrainer::evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders) {
  return score_views(
      views, [](const DatasetView& view) { return view.camera; }, [&](const Camera& camera) { return render(camera); },
      renders);
}

void NerfTrainer::check_finite(int iteration) const {
  if (!all_finite(model_.coarse.parameters())) throw TrainingDiverged(iteration, "coarse_network");
  if (!all_finite(model_.fine.parameters())) throw TrainingDiverged(iteration, "fine_network");
}

void NerfTrainer::save_checkpoint(const std::filesystem::path& file) const {
  write_stream_atomically(file, [&](std::ostream& out) {
    out.write(kCheckpointMagic, sizeof(kCheckpointMagic));
    out.write(reinterpret_cast<const char*>(&kCheckpointVersion), sizeof(kCheckpointVersion));
    const std::int64_t iteration = iteration_, steps = coarse_adam_.steps();
    out.write(reinterpret_cast<const char*>(&iteration), sizeof(iteration));
    out.write(reinterpret_cast<const char*>(&steps), sizeof(steps));
    std::ostringstream rng_text;
    rng_text << rng_;
    const std::string rng = rng_text.str();
    const std::uint64_t rng_length = rng.size();
    out.write(reinterpret_cast<const char*>(&rng_length), sizeof(rng_length));
    out.write(rng.data(), std::streamsize(rng.size()));
    const std::string settings = to_json(config_).dump();
    const std::uint64_t settings_length = settings.size();
    out.write(reinterpret_cast<const char*>(&settings_length), sizeof(settings_length));
    out.write(settings.data(), std::streamsize(settings.size()));
    write_nerf_to(out, model_);
    write_nerf_to(out, last_good_model_);
    write_floats(out, coarse_adam_.first_moment());
    write_floats(out, coarse_adam_.second_moment());
    write_floats(out, fine_adam_.first_moment());
    write_floats(out, fine_adam_.second_moment());
    write_floats(out, averaged_.coarse.parameters());
    write_floats(out, averaged_.fine.parameters());
  });
}

void NerfTrainer::load_checkpoint(const std::filesystem::path& file, const GivenSettings& given) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "cannot open the checkpoint");
  char magic[8] = {};
  std::uint32_t version = 0;
  in.read(magic, sizeof(magic));
  in.read(reinterpret_cast<char*>(&version), sizeof(version));
  if (!in || std::memcmp(magic, kCheckpointMagic, sizeof(magic)) != 0)
    throw InputError(file, "not a NeRF checkpoint");
  if (version < 1 || version > kCheckpointVersion) throw InputError(file, "unsupported NeRF checkpoint version");
  std::int64_t iteration = 0, steps = 0;
  std::uint64_t rng_length = 0;
  in.read(reinterpret_cast<char*>(&iteration), sizeof(iteration));
  in.read(reinterpret_cast<char*>(&steps), sizeof(steps));
  in.read(reinterpret_cast<char*>(&rng_length), sizeof(rng_length));
  if (!in || rng_length > 100000) throw InputError(file, "truncated checkpoint header");
  if (iteration < 0 || iteration > kMaxTrainingIterations || steps < 0 || steps > kMaxTrainingIterations)
    throw InputError(file, "the iteration or optimiser step count is outside [0, " +
                               std::to_string(kMaxTrainingIterations) + "]");
  std::string rng(rng_length, '\0');
  in.read(rng.data(), std::streamsize(rng_length));
  NerfTrainingConfig config = config_;
  if (version >= 3) {
    std::uint64_t settings_length = 0;
    in.read(reinterpret_cast<char*>(&settings_length), sizeof(settings_length));
    if (!in || settings_length > (1u << 20)) throw InputError(file, "truncated checkpoint header");
    std::string settings(settings_length, '\0');
    in.read(settings.data(), std::streamsize(settings_length));
    if (!in) throw InputError(file, "truncated checkpoint header");
    try {
      from_json(resumed_settings(nlohmann::json::parse(settings), to_json(config_), given), config);
      config = validated(config);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(file, "checkpoint settings are malformed: " + json_error_text(e));
    } catch (const ArgumentError& e) {
      throw InputError(file, e.what());
    }
  }
  NerfModel model = read_nerf_from(in, file), last_good = read_nerf_from(in, file);
  if (!(model.settings.coarse == config.model.coarse) || !(model.settings.fine == config.model.fine))
    throw InputError(file, "the checkpoint's networks differ from this run's settings");
  FlatAdam coarse_adam(model.coarse.parameter_count(), adam_settings(config)),
      fine_adam(model.fine.parameter_count(), adam_settings(config));
  read_floats(in, coarse_adam.first_moment(), file, "optimiser state");
  read_floats(in, coarse_adam.second_moment(), file, "optimiser state");
  read_floats(in, fine_adam.first_moment(), file, "optimiser state");
  read_floats(in, fine_adam.second_moment(), file, "optimiser state");
  coarse_adam.set_steps(steps);
  fine_adam.set_steps(steps);
  NerfModel averaged = model;
  if (version >= 2) {
    read_floats(in, averaged.coarse.parameters(), file, "parameter average");
    read_floats(in, averaged.fine.parameters(), file, "parameter average");
  }
  expect_end_of_file(in, file, "the checkpoint's last array");
  std::istringstream rng_text(rng);
  std::mt19937 restored_rng;
  rng_text >> restored_rng;
  if (!rng_text) throw InputError(file, "bad random state in the checkpoint");
  config_ = config;
  model_ = std::move(model);
  averaged_ = std::move(averaged);
  last_good_model_ = std::move(last_good);
  coarse_adam_ = std::move(coarse_adam);
  fine_adam_ = std::move(fine_adam);
  rng_ = restored_rng;
  iteration_ = int(iteration);
}

}  // namespace splat
