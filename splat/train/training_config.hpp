#pragma once
// Every setting of the Gaussian-splatting trainer in one struct with the official 3DGS
// defaults. The command line fills it; it is written beside every output (config.json) and
// into checkpoints, so a run can be reproduced and resumed. Its table of keys and ranges
// (training_config.cpp, splat/core/settings_table.hpp) reads, writes and validates it.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "splat/optim/density_control.hpp"
#include "splat/raster/rasterizer.hpp"
#include "splat/train/compact_settings.hpp"
#include "splat/train/training_limits.hpp"
#include "splat/train/validation_settings.hpp"

namespace splat {

// Starting points of a random initialisation: with its optimiser state a Gaussian takes
// about 1 KB, so this keeps the start under 1 GB.
constexpr double kMaxRandomInitPoints = 1'000'000;
constexpr double kMaxGaussiansSetting = 100'000'000;
// The most views one step may take (--batch): each keeps its statistics until the step ends.
constexpr int kMaxBatchViews = 256;

// The member defaults are the official recipe (strategy "official"); splat_training_preset
// gives each strategy's own defaults, which is what the command lines start from.
struct SplatTrainingConfig {
  // Density control: "official" (clone/split/prune/reset as the official trainer, bit for
  // bit) or "compact" (the model grows only while it pays; see density_strategy.hpp).
  std::string strategy = "official";
  int iterations = 30000;
  double max_seconds = 0;            // wall-clock limit, 0 = none; whichever ends first
  float background[3] = {1, 1, 1};
  unsigned seed = 0;                 // view order, initialisation, split samples
  // Views per optimiser step (--batch; splat/train/view_batch.hpp): the loss is their mean.
  // Iterations count views, so `iterations` must be a multiple of it and every schedule keeps
  // its meaning. 1 = the official one view per step.
  int batch = 1;
  // A batch's rates are the one-view rates × batch^this: 1, linear, travels as far per view
  // seen as one view a step does; Grendel-GS's square-root rule (0.5) lost 0.2-0.6 dB at an
  // equal number of views on lego400 and scenes/ where linear gained.
  float batch_lr_exponent = 1.0f;

  float ssim_weight = 0.2f;          // λ in (1 − λ)·L1 + λ·(1 − SSIM)
  // Learning rates (the position one is scaled by the scene extent and decays exponentially).
  double position_lr_init = 1.6e-4, position_lr_final = 1.6e-6;
  int position_lr_max_steps = 30000;
  // The schedules (the position step, the density strategy's phases, the appearance decay
  // below) are written for a run of position_lr_max_steps iterations. With
  // schedule_follows_budget they span the run's budget instead, whatever its length:
  // iteration i of a run of schedule_iterations counts as i × position_lr_max_steps /
  // schedule_iterations, and under a time budget (--max-seconds) the fraction f of it spent
  // counts as f × position_lr_max_steps when that is further along. Every run then ends with
  // its schedule complete (growth stopped in time to settle, the steps decayed) instead of
  // cut off mid-move. Intervals (growth every 100 iterations, SH bands every 1,000) stay in
  // real iterations.
  bool schedule_follows_budget = false;
  // The iterations the schedule spans: 0 = the run's `iterations` when it starts. The trainer
  // records the value it uses, so a resumed run keeps its schedule even when --iters extends
  // it; set it above --iters to run only the first part of a longer schedule.
  int schedule_iterations = 0;
  float sh_dc_lr = 2.5e-3f, sh_rest_lr = 2.5e-3f / 20.0f;
  float opacity_lr = 0.05f, scale_lr = 5e-3f, rotation_lr = 1e-3f;
  // The other groups' rates (SH, opacity, scale, rotation) are constant in the official
  // recipe, so the last scores of a run jitter by a few hundredths of a dB. Below 1, they
  // decay log-linearly to this factor of their rate from schedule iteration
  // appearance_lr_decay_from to position_lr_max_steps (1 = constant, the official).
  float appearance_lr_final_factor = 1.0f;
  int appearance_lr_decay_from = 0;
  // Above 0, the model a run scores and saves is an exponential moving average of the
  // parameters Adam steps through (Polyak averaging; AdamSettings::average_decay), from the
  // schedule's fraction parameter_average_from on: each step moves the average
  // (1 − parameter_average_decay) of the way to the parameters, so it spans about the last
  // 1/(1 − decay) steps. At constant rates the last iterates scatter around the minimum by
  // their gradient noise; their mean sits nearer to it. 0 = off (the official: the iterate).
  float parameter_average_decay = 0.0f;
  float parameter_average_from = 0.5f;

  int sh_degree = 3;                 // bands the model stores
  int sh_increase_interval = 1000;   // one more active band every this many iterations

  // Random initialisation, when the dataset has no point cloud (initial_model.hpp):
  // random_init_points in the cube [−h, h]³ for h = random_init_half_extent > 0 (the
  // official recipe), or with h = 0 placed by the training cameras: in the cube their views
  // share when the images leave the background out, otherwise through their frusta from
  // random_init_near to random_init_far times their distance from the scene, with
  // random_init_shell_fraction of them on a background shell at the far distance when the
  // images show a background. The frusta settings below were chosen on depth_range
  // (objects 1 to 15 units away, cameras 4 from its centre): 28.08 dB at 3,000 iterations,
  // where the official cube scored 19.93; without the shell 25.98, one depth per point 25.47.
  std::size_t random_init_points = 100000;
  float random_init_half_extent = 1.3f;
  float random_init_near = 1.0f;
  float random_init_far = 10.0f;
  float random_init_shell_fraction = 0.5f;
  // Distances drawn per frustum point, the one the other views' colours agree with most
  // kept (view_points.hpp; 1 = plain random depth).
  int random_init_depth_candidates = 8;

  // Far content's position steps (far_steps.hpp): beyond the cameras' distance D from the
  // scene's centre, a Gaussian's step is multiplied by (min(r, random_init_far·D) / D)^
  // exponent. 0 = off (the official). Only after a start through the frusta (above): a
  // point cloud places far content already, and an object in a cube has none.
  float far_position_step_exponent = 0.0f;

  DensityControlSettings density;    // includes max_gaussians (the Gaussian budget)
  CompactSettings compact;           // the compact strategy's own settings
  AlphaClampGradient alpha_clamp_gradient = AlphaClampGradient::kZero;

  // Pose refinement (--refine-poses; splat/train/pose_alignment.hpp): from iteration
  // pose_refine_from on, each training view's pose carries a correction optimised with the
  // scene (Adam, its rates decaying exponentially to pose_lr_final_factor of themselves over
  // the schedule), and before they are scored the test views are aligned to their photographs
  // by test_pose_alignment_steps pose-only steps with the model fixed, from their recorded
  // poses carried into the model's frame (splat/core/frame_change.hpp; the same rates,
  // decaying over the steps to the same factor; the best pose seen is kept).
  // Off by default, on real captures too (issue 40, bench/HISTORY.md): on real_cup and
  // real_thermos at P6 it moves the training poses 0.9° / 5.7 % and 0.16° / 2.3 % of the extent
  // each, beyond the frame they share, and the model follows them: aligned test views score
  // 30.69 and 37.03 dB (the default 30.26–30.44 and 35.79), but at the photographs' recorded
  // poses, where a user renders and the official code scores, 24.10 and 31.45.
  bool refine_poses = false;
  int pose_refine_from = 100;
  // Adam's steps are about the rate's size whatever the gradient, so on good poses the rate
  // is the jitter and the drift of the frame, and on poses 1° off it is how fast they travel.
  // Turned about the scene (below), 10⁻³ decaying to 3 % takes lego400's poses from 1° / 1 %
  // to 0.06–0.07° / 0.07–0.08 % in 10 minutes. On clean poses it costs nothing at equal
  // iterations, but about 0.1 dB in 10 minutes, since the jittering poses grow 3–10 % more
  // Gaussians and so slow every iteration.
  float pose_rotation_lr = 1e-3f;     // on the correction quaternion's components
  float pose_translation_lr = 1e-3f;  // on the translation, in units of the scene extent
  float pose_lr_final_factor = 0.03f;
  // The fraction of the schedule over which the rates decay (then they stay at the final
  // rate): below 1, poses travel early and are held still while the detail is built.
  float pose_lr_decay_until = 1.0f;
  // Turn each correction about the scene's centre's depth on the camera's optical axis
  // instead of the camera centre: the image's shift and its parallax become separate
  // coordinates (apply_pose_correction), so the weakly seen parallax is not left behind.
  bool pose_pivot_at_scene = true;
  // Adam's first-moment decay for the corrections. A view's correction is stepped only when
  // that view is trained on; on good poses its gradient is mostly noise, which a longer
  // average (closer to 1) cancels, while on bad poses it points the same way every time.
  float pose_adam_beta1 = 0.9f;
  // After every pose step, take out of the corrections the similarity they share
  // (PoseRefiner::hold_frame), so the frame stays the recorded poses' and the model need not
  // follow a drifting one. lego400 at 6,000 iterations (one thread): clean + refinement grew
  // 74,158 Gaussians free and 71,478 held (plain: 70,185), at 33.71 / 33.68 dB (plain 33.66);
  // 1° / 1 % + refinement held scored 31.31.
  bool pose_hold_frame = true;
  // 100 rather than 30: on lego400's refined models, 30 steps from the recorded poses left
  // 0.3–0.6 dB that 100 recovered, and 300 add under 0.1.
  int test_pose_alignment_steps = 100;

  // Exposure compensation (--exposure-compensation; splat/train/exposure_compensation.hpp):
  // from iteration exposure_from on, each training view's render passes through its own
  // affine colour map, optimised with the scene (Adam at exposure_lr, decaying as the
  // appearance rates do); the maps' mean stays the identity, and test views use none.
  bool exposure_compensation = false;
  int exposure_from = 500;
  float exposure_lr = 1e-3f;

  // A validation set taken from the training views decides whether the model of the end of
  // growth or the best one seen before is kept (validation_holdout.hpp). Off in the
  // official recipe; the compact one holds one view in 32 out on a real capture.
  ValidationSettings validation;

  int test_interval = 1000;          // iterations between test evaluations (0 = end only)
  int checkpoint_interval = 5000;    // iterations between checkpoints (0 = none)
};

// The factor on the SH, opacity, scale and rotation rates at (schedule) iteration
// `iteration`: 1 before appearance_lr_decay_from, appearance_lr_final_factor from
// position_lr_max_steps on, log-linear in between.
float appearance_lr_factor(const SplatTrainingConfig& config, double iteration);

// Where (1-based) iteration `iteration` stands in the schedule's terms, with
// `time_budget_fraction` of a time budget spent (0 without one): the iteration itself, or
// scaled to the run's budget under schedule_follows_budget (see there).
double schedule_iteration(const SplatTrainingConfig& config, int iteration, double time_budget_fraction);

// The strategies splat-train knows, in the order the help lists them.
inline const char* const kSplatStrategies[] = {"compact", "official"};

// Every setting at the defaults of `strategy`; ArgumentError for an unknown name.
SplatTrainingConfig splat_training_preset(const std::string& strategy);

// Throws ArgumentError naming the first setting outside its range (the table's, the same a
// config file is read with) or at odds with another (random_init_near not below
// random_init_far, iterations not a multiple of the batch, a batch with pose refinement or
// exposure compensation). The trainer and initial_model call it.
void validate(const SplatTrainingConfig& config);

nlohmann::json to_json(const SplatTrainingConfig& config);
// Reads the fields present in `json` over `config` (defaults for the rest); throws
// ArgumentError naming an unknown key or a value of the wrong type. A "strategy" key first
// resets `config` to that strategy's preset, so the file's other fields apply over the
// defaults of the strategy it names.
void from_json(const nlohmann::json& json, SplatTrainingConfig& config);

}  // namespace splat
