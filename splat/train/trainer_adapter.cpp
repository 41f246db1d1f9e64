#include "splat/train/trainer_adapter.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "splat/data/orbit_cameras.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/nerf/nerf_file.hpp"
#include "splat/train/nerf_scene_space.hpp"
#include "splat/train/nerf_trainer.hpp"

namespace splat {

namespace {

// Views one step trains on: the splats' batch; the NeRF's steps are batches of rays.
int views_per_step(const SplatTrainingConfig& config) { return config.batch; }
int views_per_step(const NerfTrainingConfig&) { return 1; }

// What both adapters forward to their trainer unchanged (the trainers share these names).
template <class Trainer, class Config>
class DelegatingAdapter : public TrainerAdapter {
 public:
  DelegatingAdapter(const Dataset& dataset, const Config& config) : trainer_(dataset, config) {
    // SPLAT_FAULT_NAN_AT_ITERATION=N: a parameter becomes NaN after step N, which the
    // divergence check then finds as it would a real blow-up (docs/DESIGN.md, "Errors").
    if (const char* at = std::getenv("SPLAT_FAULT_NAN_AT_ITERATION")) fault_iteration_ = std::atoi(at);
  }
  RunSchedule schedule() const override {
    const auto& c = trainer_.config();
    return {c.iterations, c.max_seconds, c.test_interval, c.checkpoint_interval, views_per_step(c)};
  }
  StepResult step() override {
    const StepResult result = trainer_.step();
    if (trainer_.iteration() == fault_iteration_) {
      trainer_.inject_non_finite_parameter();
      trainer_.check_parameters_finite();
    }
    return result;
  }
  void set_time_budget_fraction(double fraction) override { trainer_.set_time_budget_fraction(fraction); }
  Evaluation evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders) override {
    return trainer_.evaluate(views, renders);
  }
  int iteration() const override { return trainer_.iteration(); }
  void check_parameters_finite() const override { trainer_.check_parameters_finite(); }
  void save_checkpoint(const std::filesystem::path& file) const override { trainer_.save_checkpoint(file); }
  void load_checkpoint(const std::filesystem::path& file, const GivenSettings& given) override {
    trainer_.load_checkpoint(file, given);
  }
  nlohmann::json config_json() const override { return to_json(trainer_.config()); }

 protected:
  Trainer trainer_;
  int fault_iteration_ = -1;
};

class SplatAdapter final : public DelegatingAdapter<SplatTrainer, SplatTrainingConfig> {
 public:
  using DelegatingAdapter::DelegatingAdapter;
  std::string method() const override { return "splat"; }
  bool finished() const override { return trainer_.finished(); }
  std::string finished_summary() const override { return trainer_.validation().restore_summary(); }
  void set_process_group(ProcessGroup* group) override { trainer_.set_process_group(group); }
  std::size_t num_gaussians() const override { return trainer_.model().size(); }
  std::size_t num_params() const override {
    const GaussianModel& m = trainer_.model();
    return m.size() * (3 + 3 + 4 + 1 + std::size_t(m.sh_coefficients()) * 3);
  }
  std::string model_size() const override { return std::to_string(num_gaussians()) + " Gaussians"; }
  std::string model_file_name() const override { return "model.ply"; }
  void write_model(const std::filesystem::path& file) const override { write_ply(trainer_.output_model(), file); }
  void write_last_good_model(const std::filesystem::path& file) const override {
    write_ply(trainer_.last_good_model(), file);
  }
  std::vector<Camera> refined_training_cameras() const override {
    return trainer_.config().refine_poses ? trainer_.training_cameras() : std::vector<Camera>{};
  }
  void add_metrics(nlohmann::json& m) const override {
    m["scene_extent"] = trainer_.scene_extent();
    m["initialisation"] = to_json(trainer_.initialisation());
    m["strategy"] = trainer_.strategy().name();
    m["density_control"] = trainer_.strategy().metrics();
    if (const nlohmann::json v = trainer_.validation().metrics(); !v.is_null()) m["validation"] = v;
    if (const ResolutionSchedule& r = trainer_.resolution_schedule(); r.start_divisor() > 1)
      m["resolution_warmup"] = {{"start_divisor", r.start_divisor()}, {"steps", r.steps()}};
    if (const std::optional<int> start = trainer_.parameter_average_start())
      m["parameter_average"] = {{"decay", trainer_.config().parameter_average_decay}, {"from_iteration", *start}};
    if (trainer_.config().refine_poses) m["pose_refinement"] = pose_refinement_metrics();
    if (trainer_.config().exposure_compensation) m["exposure_compensation"] = exposure_metrics();
  }

 private:
  // How far the training views' exposure maps moved, and how the test views were scored.
  nlohmann::json exposure_metrics() const {
    const ExposureCompensation& maps = trainer_.exposure_compensation();
    double mean_gain = 0, max_gain = 0, mean_offset = 0;
    for (std::size_t v = 0; v < maps.views(); ++v)
      for (int c = 0; c < 3; ++c) {
        const double gain = std::abs(maps.parameters(v)[c]), offset = std::abs(maps.parameters(v)[3 + c]);
        mean_gain += gain;
        max_gain = std::max(max_gain, gain);
        mean_offset += offset;
      }
    const double values = 3.0 * double(std::max<std::size_t>(1, maps.views()));
    nlohmann::json j;
    j["training_views"] = maps.views();
    j["mean_abs_log_gain"] = mean_gain / values;
    j["max_abs_log_gain"] = max_gain;
    j["mean_abs_offset"] = mean_offset / values;
    j["test_protocol"] = "test views are rendered without a map: the training views' mean exposure";
    return j;
  }

  // How far refinement moved the training views, and how the test views were scored.
  nlohmann::json pose_refinement_metrics() const {
    const PoseRefiner& refiner = trainer_.pose_refiner();
    double rotation_deg = 0, translation = 0;
    for (std::size_t v = 0; v < refiner.views(); ++v) {
      const glm::vec4 q = glm::normalize(refiner.correction(v).rotation);
      rotation_deg += 2.0 * std::acos(std::min(1.0, std::abs(double(q[0])))) * 180.0 / 3.14159265358979323846;
      translation += glm::length(refiner.correction(v).translation);
    }
    const double views = std::max<std::size_t>(1, refiner.views());
    nlohmann::json j;
    j["training_views"] = refiner.views();
    j["mean_rotation_correction_deg"] = rotation_deg / views;
    j["mean_translation_correction"] = translation / views;
    j["test_protocol"] =
        "each test view's pose is first carried into the model's frame by the similarity the training "
        "views' poses moved by, then aligned to its photograph by " +
        std::to_string(trainer_.config().test_pose_alignment_steps) +
        " pose-only Adam steps with the model fixed, then scored";
    if (const std::optional<double> psnr = trainer_.test_psnr_at_recorded_poses())
      j["test_psnr_at_recorded_poses"] = *psnr;
    return j;
  }
};

class NerfAdapter final : public DelegatingAdapter<NerfTrainer, NerfTrainingConfig> {
 public:
  using DelegatingAdapter::DelegatingAdapter;
  std::string method() const override { return trainer_.config().method; }
  std::size_t num_gaussians() const override { return 0; }
  std::size_t num_params() const override { return trainer_.model().parameter_count(); }
  std::string model_size() const override {
    char text[64];
    std::snprintf(text, sizeof(text), "%.2fM parameters, %zu/%zu cells occupied",
                  double(num_params()) * 1e-6, trainer_.model().grid.occupied_count(),
                  trainer_.model().grid.cell_count());
    return text;
  }
  std::string model_file_name() const override { return "model" + nerf_file_extension(trainer_.model().settings); }
  void write_model(const std::filesystem::path& file) const override { write_nerf(trainer_.model(), file); }
  void write_last_good_model(const std::filesystem::path& file) const override {
    write_nerf(trainer_.last_good_model(), file);
  }
  void add_metrics(nlohmann::json& m) const override {
    m["occupied_cells"] = trainer_.model().grid.occupied_count();
    const NerfTrainer::SampleCounts& counts = trainer_.sample_counts();
    const double steps = double(std::max<std::uint64_t>(1, counts.steps));
    m["samples_per_iteration"] = {{"rays", trainer_.config().rays_per_batch},
                                  {"coarse", double(counts.coarse) / steps},
                                  {"fine", double(counts.fine) / steps}};
  }
};

// Where the NeRF samples follows the data (nerf_scene_space.hpp), unless the config gives a
// box; the configured box is also the fallback when the data does not say.
NerfTrainingConfig with_scene_space(NerfTrainingConfig config, const Dataset& dataset) {
  if (!config.box_from_data) return config;
  const SceneSpace space = scene_space_from_data(dataset, config.model.box);
  config.model.box = space.box;
  config.model.unbounded = space.unbounded;
  return config;
}

}  // namespace

std::unique_ptr<TrainerAdapter> make_trainer(const std::string& method, const SplatTrainingConfig& splat_config,
                                             const NerfTrainingConfig& nerf_config, const Dataset& dataset) {
  if (method == "nerf" || method == "ngp") {
    if (nerf_config.method != method)
      throw ArgumentError("make_trainer: a " + method + " run needs the " + method + " preset's config, not " +
                          nerf_config.method + "'s");
    return std::make_unique<NerfAdapter>(dataset, with_scene_space(nerf_config, dataset));
  }
  return std::make_unique<SplatAdapter>(dataset, splat_config);
}

std::vector<std::filesystem::path> write_view_cameras(const TrainerAdapter& trainer, const Dataset& dataset,
                                                      const std::filesystem::path& folder) {
  const auto names_of = [](const std::vector<DatasetView>& views) {
    std::vector<std::string> names;
    for (const DatasetView& view : views) names.push_back(view.name);
    return names;
  };
  std::vector<Camera> trained = trainer.refined_training_cameras();
  if (trained.empty()) trained = cameras_of(dataset.train);
  std::vector<std::filesystem::path> written{folder / kTrainCamerasFileName};
  write_transforms(written.back(), trained, names_of(dataset.train));
  const std::filesystem::path test_file = folder / kTestCamerasFileName;
  if (dataset.test.empty()) {
    std::filesystem::remove(test_file);  // an earlier run's, of other views
    return written;
  }
  write_transforms(test_file, cameras_of(dataset.test), names_of(dataset.test));
  written.push_back(test_file);
  return written;
}

std::optional<std::filesystem::path> training_cameras_in(const std::filesystem::path& folder) {
  const std::filesystem::path file = folder / kTrainCamerasFileName;
  std::error_code ec;
  if (std::filesystem::is_regular_file(file, ec)) return file;
  return std::nullopt;
}

}  // namespace splat
