#include "splat/optim/density_control.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/gaussians/covariance.hpp"

namespace splat {
namespace {

float max_scale(const GaussianModel& model, std::size_t i) {
  const Vec3<float> s = model.scale(i);
  return std::max({s[0], s[1], s[2]});
}

void require_model_shape(const GaussianModel& model, const GaussianModel& moment,
                         const char* name) {
  if (moment.sh_degree != model.sh_degree || moment.size() != model.size())
    throw ArgumentError(std::string("density control: the Adam ") + name + " holds " +
                        std::to_string(moment.size()) + " rows, the model " +
                        std::to_string(model.size()) + " (call AdamState::reset_like)");
}

}  // namespace

void AlignedRows::append_copies(const std::vector<std::size_t>& sources, const GaussianModel& born) {
  model.append_rows(born);
  for (GaussianModel* state : adam.rows()) state->append_zero_rows(sources.size());
  for (std::vector<float>* array : stats)
    for (std::size_t s : sources) array->push_back((*array)[s]);
}

void AlignedRows::keep(const std::vector<std::uint8_t>& flags) {
  model.keep_rows(flags);
  for (GaussianModel* state : adam.rows()) state->keep_rows(flags);
  for (std::vector<float>* array : stats) {
    std::size_t out = 0;
    for (std::size_t i = 0; i < flags.size(); ++i)
      if (flags[i]) (*array)[out++] = (*array)[i];
    array->resize(out);
  }
}

DensifyCandidates select_densify_candidates(const GaussianModel& model,
                                            const std::vector<float>& grads,
                                            const DensityControlSettings& settings,
                                            float scene_extent) {
  const std::size_t n = model.size();
  const float clone_limit = float(settings.percent_dense * double(scene_extent));
  std::vector<std::uint8_t> is_clone(n, 0), is_split(n, 0);
  std::vector<std::size_t> all;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(grads[i] >= settings.densify_grad_threshold)) continue;
    (max_scale(model, i) <= clone_limit ? is_clone : is_split)[i] = 1;
    all.push_back(i);
  }

  DensifyCandidates out;
  if (settings.max_gaussians > 0) {
    // Largest mean gradient first, then lower index: a total order, so the choice is unique.
    std::sort(all.begin(), all.end(), [&](std::size_t a, std::size_t b) {
      return grads[a] > grads[b] || (grads[a] == grads[b] && a < b);
    });
    std::size_t room = settings.max_gaussians > n ? settings.max_gaussians - n : 0;
    const std::size_t split_growth = std::size_t(settings.split_count - 1);
    for (std::size_t i : all) {
      const std::size_t growth = is_clone[i] ? 1 : split_growth;
      if (growth <= room) {
        room -= growth;
      } else {
        is_clone[i] = is_split[i] = 0;
        ++out.over_budget;
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (is_clone[i]) out.clone.push_back(i);
    if (is_split[i]) out.split.push_back(i);
  }
  return out;
}

GaussianModel split_offspring(const GaussianModel& model, const std::vector<std::size_t>& sources,
                              const DensityControlSettings& settings, std::mt19937& rng,
                              std::vector<std::size_t>& offspring_sources) {
  offspring_sources.clear();
  for (int c = 0; c < settings.split_count; ++c)
    offspring_sources.insert(offspring_sources.end(), sources.begin(), sources.end());
  GaussianModel born = model.gather_rows(offspring_sources);

  std::vector<float> z(born.size() * 3);
  fill_standard_normal(rng, z.data(), z.size());
  for (std::size_t r = 0; r < born.size(); ++r) {
    float* mean = &born.means[3 * r];
    float* log_scale = &born.log_scales[3 * r];
    const Mat3<float> rotation = born.rotation(r);
    const Vec3<float> scale = born.scale(r);
    Vec3<float> sample;
    for (int a = 0; a < 3; ++a) {
      sample[a] = scale[a] * z[3 * r + a];
      log_scale[a] = std::log(scale[a] / settings.split_scale_divisor);
    }
    const Vec3<float> offset = rotation * sample;
    for (int a = 0; a < 3; ++a) mean[a] += offset[a];
  }
  return born;
}

void DensificationStats::reset(std::size_t n) {
  grad_accum.assign(n, 0.0f);
  denom.assign(n, 0.0f);
  max_radii.assign(n, 0.0f);
}

void DensificationStats::keep_rows(const std::vector<std::uint8_t>& keep) {
  if (keep.size() != size())
    throw ArgumentError("DensificationStats::keep_rows: " + std::to_string(keep.size()) +
                        " flags for " + std::to_string(size()) + " rows");
  for (std::vector<float>* array : {&grad_accum, &denom, &max_radii}) {
    std::size_t out = 0;
    for (std::size_t i = 0; i < keep.size(); ++i)
      if (keep[i]) (*array)[out++] = (*array)[i];
    array->resize(out);
  }
}

DensityControl::DensityControl(const DensityControlSettings& settings,
                               std::size_t gaussian_count)
    : settings_(settings) {
  if (settings.split_count < 1)
    throw ArgumentError("DensityControl: split count " + std::to_string(settings.split_count) +
                        " must be at least 1");
  if (settings.densification_interval < 1 || settings.opacity_reset_interval < 1)
    throw ArgumentError("DensityControl: intervals must be at least 1");
  stats_.reset(gaussian_count);
}

void DensityControl::add_stats(std::span<const float> view_grad_norms,
                               std::span<const std::int32_t> radii) {
  const std::size_t n = stats_.size();
  if (view_grad_norms.size() != n || radii.size() != n)
    throw ArgumentError("DensityControl::add_stats: " + std::to_string(view_grad_norms.size()) +
                        " gradient norms and " + std::to_string(radii.size()) +
                        " radii for " + std::to_string(n) + " Gaussians");
  for (std::size_t i = 0; i < n; ++i) {
    if (radii[i] <= 0) continue;
    stats_.grad_accum[i] += view_grad_norms[i];
    stats_.denom[i] += 1.0f;
    stats_.max_radii[i] = std::max(stats_.max_radii[i], float(radii[i]));
  }
}

DensityControlReport DensityControl::densify_and_prune(GaussianModel& model, AdamState& adam,
                                                       float scene_extent,
                                                       std::optional<float> max_screen_size,
                                                       std::mt19937& rng) {
  model.check_consistent();
  require_model_shape(model, adam.first_moment, "first moment");
  require_model_shape(model, adam.second_moment, "second moment");
  const std::size_t n = model.size();
  if (stats_.size() != n)
    throw ArgumentError("DensityControl::densify_and_prune: statistics for " +
                        std::to_string(stats_.size()) + " Gaussians, the model has " +
                        std::to_string(n));

  DensityControlReport report;
  report.densified = true;

  // Mean view-space gradient; never-seen Gaussians (0/0 in the official) count as 0.
  std::vector<float> grads(n, 0.0f);
  for (std::size_t i = 0; i < n; ++i)
    if (stats_.denom[i] > 0) grads[i] = stats_.grad_accum[i] / stats_.denom[i];
  const DensifyCandidates candidates = select_densify_candidates(model, grads, settings_, scene_extent);
  report.cloned = candidates.clone.size();
  report.split = candidates.split.size();
  report.over_budget = candidates.over_budget;

  std::vector<float> max_radii = stats_.max_radii;  // carried so screen-size pruning can use it
  AlignedRows rows{model, adam, {&max_radii}};

  // Clone: exact copies appended after the existing rows.
  rows.append_copies(candidates.clone, model.gather_rows(candidates.clone));

  // Split: offspring appended after the clones; the originals go below. Clones are never
  // split (their gradient counts as 0 in the official padded_grad).
  std::vector<std::size_t> offspring_sources;
  GaussianModel born =
      split_offspring(model, candidates.split, settings_, rng, offspring_sources);
  rows.append_copies(offspring_sources, born);

  // Prune, in the same pass that removes the split originals (one compaction instead of the
  // official two; the surviving rows and their order are the same).
  const std::size_t total = model.size();
  const float world_limit = float(settings_.max_world_size_factor * double(scene_extent));
  std::vector<std::uint8_t> keep(total, 1);
  for (std::size_t i : candidates.split) keep[i] = 0;
  for (std::size_t i = 0; i < total; ++i) {
    if (!keep[i]) continue;
    bool prune = model.opacity(i) < settings_.min_opacity;
    if (max_screen_size) {
      if (settings_.prune_by_screen_size && max_radii[i] > *max_screen_size) prune = true;
      if (max_scale(model, i) > world_limit) prune = true;
    }
    if (prune) {
      keep[i] = 0;
      ++report.pruned;
    }
  }
  rows.keep(keep);

  stats_.reset(model.size());
  report.count_after = model.size();
  return report;
}

DensityControlReport DensityControl::step(int iteration, GaussianModel& model, AdamState& adam,
                                          std::span<const float> view_grad_norms,
                                          std::span<const std::int32_t> radii,
                                          float scene_extent, std::mt19937& rng, bool stats_only,
                                          int views) {
  DensityControlReport report;
  const DensityControlSettings& s = settings_;
  if (gathers_stats_at(iteration)) {
    add_stats(view_grad_norms, radii);
    if (stats_only) {
      report.count_after = model.size();
      return report;
    }
    if (iteration > s.densify_from_iter && step_reaches_multiple(iteration, views, s.densification_interval)) {
      // Screen and world size limits start after the first opacity reset.
      const std::optional<float> size_threshold =
          iteration > s.opacity_reset_interval ? std::optional<float>(s.max_screen_size)
                                               : std::nullopt;
      report = densify_and_prune(model, adam, scene_extent, size_threshold, rng);
    }
    if (resets_opacity_at(iteration, views)) {
      reset_opacity(model, adam, s.opacity_reset_value);
      report.opacity_reset = true;
    }
  }
  report.count_after = model.size();
  return report;
}

bool DensityControl::resets_opacity_at(int iteration, int views) const {
  const DensityControlSettings& s = settings_;
  return iteration < s.densify_until_iter &&
         (step_reaches_multiple(iteration, views, s.opacity_reset_interval) ||
          (s.white_background && step_reaches(iteration, views, s.densify_from_iter)));
}

void reset_opacity(GaussianModel& model, AdamState& adam, float cap) {
  require_model_shape(model, adam.first_moment, "first moment");
  require_model_shape(model, adam.second_moment, "second moment");
  for (float& stored : model.opacity_logits) stored = logit(std::min(sigmoid(stored), cap));
  for (GaussianModel* state : adam.rows()) std::fill(state->opacity_logits.begin(), state->opacity_logits.end(), 0.0f);
}

}  // namespace splat
