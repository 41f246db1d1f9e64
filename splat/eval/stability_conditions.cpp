#include "splat/eval/stability_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <glm/gtx/rotate_vector.hpp>
#include <random>

#include "splat/core/error.hpp"
#include "splat/eval/metrics.hpp"

namespace splat {

namespace {

// A direction uniform on the unit sphere (normalised Gaussian vector).
glm::dvec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (;;) {
    const glm::dvec3 v(normal(rng), normal(rng), normal(rng));
    const double length = glm::length(v);
    if (length > 1e-9) return v / length;
  }
}

}  // namespace

Dataset with_training_views(const Dataset& dataset, int count) {
  if (count < 1) throw ArgumentError("a condition needs at least one training view");
  Dataset reduced = dataset;
  keep_training_views(reduced, count);
  return reduced;
}

Dataset with_pose_noise(const Dataset& dataset, double rotation_deg, double translation_fraction,
                        unsigned seed) {
  Dataset noisy = dataset;
  std::mt19937 rng(seed);
  const double angle = glm::radians(rotation_deg);
  const double shift = translation_fraction * double(dataset.scene_extent);
  for (DatasetView& view : noisy.train) {
    Camera& camera = view.camera;
    const glm::dvec3 axis = random_direction(rng), offset = random_direction(rng) * shift;
    // With x_cam = R·(x − c): the turned camera is R' = R·Q (R'ᵀR = Qᵀ, a turn by exactly
    // the angle), the moved centre c' = c + offset, and t' = −R'·c'.
    const glm::dmat3 rotation(camera.camera_from_world_rotation);
    const glm::dvec3 centre(camera.center_in_world());
    const glm::dmat3 turn(glm::rotate(glm::dmat4(1.0), angle, axis));
    const glm::dmat3 new_rotation = rotation * turn;
    const glm::dvec3 new_centre = centre + offset;
    camera.camera_from_world_rotation = glm::mat3(new_rotation);
    camera.camera_from_world_translation = glm::vec3(-(new_rotation * new_centre));
  }
  return noisy;
}

Dataset without_point_cloud(const Dataset& dataset) {
  Dataset copy = dataset;
  copy.points.reset();
  return copy;
}

double background_only_psnr(const std::vector<DatasetView>& test, const float background[3]) {
  if (test.empty()) throw ArgumentError("no test views to score the background against");
  double sum = 0;
  for (const DatasetView& view : test) {
    Image blank(view.image.width, view.image.height, view.image.channels);
    for (int y = 0; y < blank.height; ++y)
      for (int x = 0; x < blank.width; ++x)
        for (int c = 0; c < blank.channels; ++c) blank.at(x, y, c) = background[c % 3];
    sum += psnr(blank, view.image);
  }
  return sum / double(test.size());
}

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::kOk: return "ok";
    case Verdict::kDegraded: return "degraded";
    case Verdict::kFailed: return "failed";
    case Verdict::kDiverged: return "diverged";
    case Verdict::kCollapsed: return "collapsed";
  }
  return "unknown";
}

double VerdictRules::failure_psnr(double background_psnr) const {
  return std::max(background_psnr + failure_margin_db, failure_floor_db);
}

Verdict classify_run(bool diverged, double psnr, double background_psnr,
                     std::optional<double> baseline_psnr, const VerdictRules& rules) {
  if (diverged) return Verdict::kDiverged;
  if (!(psnr > background_psnr + rules.collapse_margin_db)) return Verdict::kCollapsed;
  if (psnr < rules.failure_psnr(background_psnr)) return Verdict::kFailed;
  if (baseline_psnr && psnr < *baseline_psnr - rules.degrade_db) return Verdict::kDegraded;
  return Verdict::kOk;
}

}  // namespace splat
