#pragma once
// Settings of the compact density strategy (compact_strategy.hpp), part of the training
// config (config.json keys "compact_<name>").
namespace splat {

struct CompactSettings {
  // Resolution warm-up (resolution_schedule.hpp): until schedule iteration `warmup_until`
  // the images are trained at reduced size, 1/warmup_divisor at most (1 = off), the size
  // growing by halving steps or with the images' spectrum.
  int warmup_divisor = 1;
  int warmup_until = 0;
  bool warmup_by_spectrum = false;

  // Growth, every grow_interval iterations after grow_from up to grow_until: Gaussians whose
  // mean view-space gradient reaches grow_grad_threshold are cloned (small) or split
  // (large) as the official recipe does, the largest gradients first, at most
  // grow_max_fraction × N new Gaussians per step.
  int grow_from = 500;
  int grow_until = 15000;
  int grow_interval = 100;
  float grow_grad_threshold = 2e-4f;
  double grow_max_fraction = 0.05;
  // Instead of cloning and splitting the candidates, add as many copies of live Gaussians
  // drawn with probability ∝ opacity, reshaped so the image does not change (relocation.hpp).
  bool grow_by_sampling = false;
  // At growth steps, move transparent Gaussians onto live ones (drawn ∝ opacity) instead of
  // pruning them: the count is kept, the dead capacity reused.
  bool relocate_dead = false;

  // Pruning: at every growth step, Gaussians below prune_opacity; at the end of every
  // window of prune_window iterations (0 = two epochs of the training views, the shortest
  // window sure to hold every view, and at least grow_interval) from grow_from to
  // prune_until, Gaussians whose blending weight summed over the window (in full-size
  // pixels) is below prune_weight: they made nothing visible.
  float prune_opacity = 0.005f;
  float prune_weight = 0.0f;
  // Compare prune_weight with the largest blending weight in any one view of the window
  // instead of the sum: a Gaussian drawn strongly in a few views only (a highlight, a
  // silhouette) is kept, one drawn faintly everywhere is not.
  bool prune_by_peak_weight = false;
  // The threshold once growth has stopped (0 = prune_weight). While the model grows, a strict
  // threshold removes Gaussians still on their way to a structure (a thin bar is lost early
  // and not regrown); once it has stopped, what stays faint is haze.
  float prune_weight_after_growth = 0.0f;
  int prune_window = 0;
  int prune_until = 30000;
  // At the end of every window, Gaussians drawn (a peak weight of at least prune_weight, in
  // full-size pixels) by fewer than this share of the window's views are pruned too: what one
  // or two views of many ask for explains those photographs, not the scene. On real captures
  // such Gaussians sit close in front of the one camera that draws them and spoil the test
  // views that pass by (bench/HISTORY.md, issue 40). 0 = off.
  float prune_min_view_share = 0.0f;
  // The opacity decay and the view-share prune act only on data with a point cloud (a real
  // capture), where they were chosen; synthetic data keeps its resets and what few views draw
  // (density_strategy.hpp's compact_settings_for). The preset's is true.
  bool real_capture_only = false;
  // At the end of every window, to the end of the run, Gaussians inside a training camera's
  // frame nearer than this factor × that camera's near bound (the depth its structure-from-
  // motion points begin at, points_near_bounds.hpp) are pruned: they sit in space the capture
  // shows empty, in front of everything the photographs were matched on. Only on data with a
  // point cloud (COLMAP); 0 = off.
  float prune_before_points = 0.0f;

  // Opacity decay (Binocular3DGS, Han et al. 2024): after every optimiser step from grow_from
  // to grow_until, each opacity loses this fraction of itself (o ← (1 − d)·o). A Gaussian the
  // photographs keep asking for is pushed back up by its gradient; one they barely constrain
  // (a floater in space the views see through) fades until pruning takes it. Meant in place
  // of the resets: from opacity_decay_from (a point of the schedule, as grow_until) the
  // resets stop and the decay runs; before it the resets run as set. 0 = off.
  float opacity_decay = 0.0f;
  int opacity_decay_from = 0;

  // Opacity reset as the official recipe (0 = never).
  int opacity_reset_interval = 0;
  float opacity_reset_value = 0.01f;

  // MCMC-style terms (Kheradmand et al. 2024): L1 regularisers on opacity and scale (means
  // over the model) and position noise scaled by the means' learning rate, strongest for
  // transparent Gaussians. 0 = off.
  float opacity_regularization = 0.0f;
  float scale_regularization = 0.0f;
  float noise_lr = 0.0f;
};

}  // namespace splat
