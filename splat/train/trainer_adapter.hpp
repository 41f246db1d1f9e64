#pragma once
// One face for the two trainers, so the command line runs either the same way: the same
// loop, progress, history, test renders, checkpoints, Ctrl-C and divergence handling.
#include <filesystem>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "splat/data/dataset.hpp"
#include "splat/core/error.hpp"
#include "splat/train/process_group.hpp"
#include "splat/train/splat_trainer.hpp"
#include "splat/train/nerf_trainer.hpp"

namespace splat {

// The limits and intervals the loop needs, whichever the method.
struct RunSchedule {
  int iterations = 0;
  double max_seconds = 0;
  int test_interval = 0, checkpoint_interval = 0;
  int views_per_step = 1;  // a step advances the iteration count by this (--batch)
};

class TrainerAdapter {
 public:
  virtual ~TrainerAdapter() = default;
  virtual std::string method() const = 0;         // "splat" | "nerf" | "ngp"
  virtual RunSchedule schedule() const = 0;
  virtual StepResult step() = 0;
  // The fraction of the time budget spent, before each step of a run that has one.
  virtual void set_time_budget_fraction(double fraction) = 0;
  virtual Evaluation evaluate(const std::vector<DatasetView>& views, std::vector<Image>* renders) = 0;
  // The training views' cameras as trained, when the method corrects them (pose refinement);
  // otherwise none.
  virtual std::vector<Camera> refined_training_cameras() const { return {}; }
  virtual int iteration() const = 0;
  // Whether training has ended by the method's own decision (the splats' validation holdout
  // restored its best model): the loop stops before another step.
  virtual bool finished() const { return false; }
  // Once finished(): a line telling the user why (empty when there is nothing to say).
  virtual std::string finished_summary() const { return {}; }
  // Shares the steps with the other ranks of a data-parallel run (null: alone). The NeRF
  // trains in one process: ArgumentError for a group of more than one.
  virtual void set_process_group(ProcessGroup* group) {
    if (group && group->size() > 1)
      throw ArgumentError("the NeRF trains in one process; data-parallel training over " +
                          std::to_string(group->size()) + " ranks is for the splats (--method splat)");
  }
  virtual std::size_t num_gaussians() const = 0;  // 0 for the NeRF
  virtual std::size_t num_params() const = 0;
  virtual std::string model_size() const = 0;     // for the progress line
  virtual void check_parameters_finite() const = 0;
  virtual void save_checkpoint(const std::filesystem::path& file) const = 0;
  virtual void load_checkpoint(const std::filesystem::path& file, const GivenSettings& given) = 0;
  virtual std::string model_file_name() const = 0;  // "model.ply" | "model.nerf" | "model.ngp"
  virtual void write_model(const std::filesystem::path& file) const = 0;
  virtual void write_last_good_model(const std::filesystem::path& file) const = 0;
  virtual nlohmann::json config_json() const = 0;
  virtual void add_metrics(nlohmann::json& metrics) const = 0;  // method-specific fields
};

// The trainer of `method` ("splat" | "nerf" | "ngp") with its settings (a NeRF method's
// config must be of its preset: nerf_training_preset); the NeRF's scene space is
// taken from the dataset unless its config fixes one.
std::unique_ptr<TrainerAdapter> make_trainer(const std::string& method, const SplatTrainingConfig& splat_config,
                                             const NerfTrainingConfig& nerf_config, const Dataset& dataset);

// Where a run leaves the cameras of the views it trained and tested on, beside the model:
// transforms JSON at the size it trained at, each frame named as its view, for any input
// format, so that splat-render --cameras and the viewer's [ ] show the user's own views. The
// training views' are their cameras as trained (corrected under pose refinement), the test
// views' their recorded ones.
inline constexpr const char* kTrainCamerasFileName = "cameras_train.json";
inline constexpr const char* kTestCamerasFileName = "cameras_test.json";
// Writes both into `folder` (atomically) and returns the files written: the test views' only
// when there are some, removing a file an earlier run in the same folder left otherwise.
std::vector<std::filesystem::path> write_view_cameras(const TrainerAdapter& trainer, const Dataset& dataset,
                                                      const std::filesystem::path& folder);
// The training views' cameras file a run left in `folder`, when it is there: what a fly-through
// and the viewer follow when given no --cameras, so that a real capture's model is seen the way
// it was photographed (its up, centre and distance) rather than framed from its Gaussians with
// world z up, which for a capture's model (its background included) misses the object.
std::optional<std::filesystem::path> training_cameras_in(const std::filesystem::path& folder);

}  // namespace splat
