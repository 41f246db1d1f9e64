#include "splat/train/evaluation.hpp"

#include <algorithm>
#include <chrono>

#include "splat/eval/half_fitted_psnr.hpp"
#include "splat/eval/metrics.hpp"
#include "splat/optim/photometric_loss.hpp"

namespace splat {

namespace {
constexpr double kFittedPsnrCeiling = 200.0;
}  // namespace

Evaluation score_views(const std::vector<DatasetView>& views, const std::function<Camera(const DatasetView&)>& camera_for,
                       const std::function<Image(const Camera&)>& render, std::vector<Image>* renders,
                       Measures measures) {
  Evaluation e;
  if (renders) renders->clear();
  double psnr_sum = 0, ssim_sum = 0, fitted_sum = 0;
  for (const DatasetView& view : views) {
    const Camera camera = camera_for(view);
    const auto start = std::chrono::steady_clock::now();
    Image image = render(camera);
    e.view_render_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    // A masked view is scored over the pixels its mask keeps; SSIM and the half-fitted PSNR
    // see both images through the mask, as the masked loss does.
    const bool has_mask = !view.mask.empty();
    const double view_psnr = has_mask ? masked_psnr(image, view.image, view.mask) : psnr(image, view.image);
    e.view_psnr.push_back(view_psnr);
    psnr_sum += view_psnr;
    if (measures == Measures::kAll) {
      const Image render_seen = has_mask ? masked(image, view.mask) : Image();
      const Image photo_seen = has_mask ? masked(view.image, view.mask) : Image();
      const Image& render_scored = has_mask ? render_seen : image;
      const Image& photo_scored = has_mask ? photo_seen : view.image;
      ssim_sum += ssim(render_scored, photo_scored);
      // An exact half scores +inf; a finite stand-in keeps the mean a number.
      if (image.width >= 2)
        fitted_sum += std::min(half_fitted_psnr(render_scored, photo_scored), kFittedPsnrCeiling);
    }
    if (renders) renders->push_back(std::move(image));
  }
  e.views = int(views.size());
  if (e.views > 0) {
    e.psnr = psnr_sum / e.views;
    e.ssim = ssim_sum / e.views;
    e.half_fitted_psnr = fitted_sum / e.views;
  }
  return e;
}

Evaluation merged(const Evaluation& a, const Evaluation& b) {
  Evaluation e = a;
  e.views = a.views + b.views;
  if (e.views > 0) {
    e.psnr = (a.psnr * a.views + b.psnr * b.views) / e.views;
    e.ssim = (a.ssim * a.views + b.ssim * b.views) / e.views;
    e.half_fitted_psnr = (a.half_fitted_psnr * a.views + b.half_fitted_psnr * b.views) / e.views;
  }
  e.view_psnr.insert(e.view_psnr.end(), b.view_psnr.begin(), b.view_psnr.end());
  e.view_render_ms.insert(e.view_render_ms.end(), b.view_render_ms.begin(), b.view_render_ms.end());
  return e;
}

}  // namespace splat
