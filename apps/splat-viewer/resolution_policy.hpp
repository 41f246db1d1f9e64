#pragma once
// How large to render the next frame. While the camera moves, a reduced resolution that
// the last renders say fits the frame-time target; once it stops, full resolution. A slow
// model (the NeRF) refines step by step instead: each still frame one level finer, so
// something is on screen at once and detail arrives over the next frames.
#include <vector>

namespace splat::viewer {

class ResolutionPolicy {
 public:
  // `levels`: render scales from coarsest to 1 (e.g. 1/8, 1/4, 1/2, 1). `progressive`: when
  // still, step one level finer per frame (slow models) instead of going straight to 1.
  ResolutionPolicy(std::vector<float> levels, double target_ms, bool progressive);

  // Records that a frame at `scale` took `ms` to render.
  void observe(float scale, double ms);
  // The scale for the next frame. `moving`: the camera changed since the last request.
  // `shown_scale`: the scale of the image now on screen for this camera (0 if none).
  float next(bool moving, float shown_scale) const;

  double target_ms() const { return target_ms_; }
  const std::vector<float>& levels() const { return levels_; }

 private:
  std::vector<float> levels_;
  double target_ms_;
  bool progressive_;
  double full_ms_ = 0;  // estimated full-resolution render time (0 = not yet known)
};

}  // namespace splat::viewer
