#pragma once
// The conditions splat-eval --stability trains under, as changes to a loaded dataset, and
// the rules that turn a run's outcome into a verdict. Test views are never changed: every
// condition is scored against the same true images and poses.
#include <optional>
#include <string>

#include "splat/data/dataset.hpp"

namespace splat {

// A copy of `dataset` with `count` of its training views (keep_training_views).
Dataset with_training_views(const Dataset& dataset, int count);

// Every training pose perturbed: the camera turned about its own centre by exactly
// `rotation_deg` about a random axis, and its centre moved by exactly
// `translation_fraction` × the scene extent in a random direction. Seeded: the same seed
// gives the same poses.
Dataset with_pose_noise(const Dataset& dataset, double rotation_deg, double translation_fraction,
                        unsigned seed);

// The dataset without its point cloud, so the splat trainer starts from random points.
Dataset without_point_cloud(const Dataset& dataset);

// The PSNR of showing only the background on every test view: what an empty model scores.
double background_only_psnr(const std::vector<DatasetView>& test, const float background[3]);

enum class Verdict { kOk, kDegraded, kFailed, kDiverged, kCollapsed };
const char* verdict_name(Verdict verdict);

struct VerdictRules {
  double collapse_margin_db = 1.0;  // collapsed: PSNR ≤ background-only PSNR + this
  // failed: PSNR below the absolute floor, the higher of background-only PSNR + this margin
  // and this many dB, whatever the baseline. A margin alone is no floor on a scene whose
  // background is far from the one rendered behind the model (depth_range's sky scores
  // 5.4 dB against black), and on a synthetic scene rendered exactly a model below 20 dB is
  // visibly wrong everywhere.
  double failure_margin_db = 3.0;
  double failure_floor_db = 20.0;
  double degrade_db = 3.0;  // degraded: PSNR < this method's baseline PSNR − this
  // Holds its best: the final PSNR is at most this far below the run's best test point. A
  // real capture's training that learns late what only its training views show ends further
  // below (issue 40's bar).
  double hold_best_db = 0.3;

  double failure_psnr(double background_psnr) const;  // the floor
};

// diverged when training stopped on a non-finite value; else collapsed when the model
// scores no better than the background alone (plus the margin); else failed when it is below
// the absolute floor (failure_psnr); else degraded when it is `degrade_db` below the same
// method's baseline run (when there is one); else ok. A baseline run can fail too.
Verdict classify_run(bool diverged, double psnr, double background_psnr,
                     std::optional<double> baseline_psnr, const VerdictRules& rules = {});

}  // namespace splat
