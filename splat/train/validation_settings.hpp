#pragma once
// Settings of the validation holdout (validation_holdout.hpp), part of the training config
// (config.json keys "validation_<name>").
namespace splat {

struct ValidationSettings {
  // One training view in `every` is held out, the most redundant ones (validation_views.hpp);
  // 0 = off. Only on data with a structure-from-motion point cloud (a real capture) and at
  // least two such views.
  int every = 0;
  int interval = 250;      // iterations between validation scores
  float decide_at = 0.5f;  // the schedule's fraction at which the holdout decides
  float fall_db = 0.3f;    // a drop from the best larger than this is a fall
};

}  // namespace splat
