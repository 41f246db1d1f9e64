#pragma once
// Scoring a model on test views, the one loop both trainers use: each view rendered (the
// render alone timed) and compared with its photograph.
#include <functional>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/core/image.hpp"
#include "splat/data/dataset.hpp"

namespace splat {

struct Evaluation {
  double psnr = 0, ssim = 0;           // means over the views; images clamped to [0, 1]
  double half_fitted_psnr = 0;         // mean over the views (half_fitted_psnr.hpp)
  int views = 0;
  std::vector<double> view_psnr;       // per view
  std::vector<double> view_render_ms;  // per view: the render alone (not choosing its camera)
};

// What score_views measures: everything, or the PSNR alone (ssim and half_fitted_psnr stay 0),
// for a score taken often inside training (the validation holdout's) that uses nothing else.
enum class Measures { kAll, kPsnrOnly };

// Scores `views`: view v is rendered by render(camera_for(v)), which returns the image
// clamped to [0, 1]. `renders`, when given, receives the images in view order.
Evaluation score_views(const std::vector<DatasetView>& views, const std::function<Camera(const DatasetView&)>& camera_for,
                       const std::function<Image(const Camera&)>& render, std::vector<Image>* renders,
                       Measures measures = Measures::kAll);

// The evaluation of a's views followed by b's.
Evaluation merged(const Evaluation& a, const Evaluation& b);

}  // namespace splat
