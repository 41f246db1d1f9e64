#pragma once
// One panel of the window: its model's render worker, the texture showing the last frame,
// and what that frame was rendered for, so the window knows when to ask for another (the
// camera moved, or a reduced frame waits to be refined).
#include <chrono>
#include <memory>

#include "apps/splat-viewer/render_worker.hpp"
#include "apps/splat-viewer/resolution_policy.hpp"

namespace splat::viewer {

// What a frame depends on: two frames with equal keys show the same picture.
struct ViewKey {
  Camera camera;
  ViewSettings settings;
  std::uint64_t model_version = 0;  // a watched model (watched_model.hpp) replaced counts up
  bool operator==(const ViewKey& other) const;
};

class PanelView {
 public:
  // `frame_finished` runs on the worker thread after each render (see RenderWorker).
  PanelView(PanelModel& model, double target_ms, std::function<void()> frame_finished);
  ~PanelView();

  // Picks up a finished frame (uploading it to the texture; needs the GL context) and, when
  // the worker is idle and the view needs it, asks for the next one. `moving`: the camera
  // changed within the last moments.
  void update(const ViewKey& key, bool moving);
  // Renders only at `scale` from now on (the benchmark's fixed phases); 0: the policy decides.
  void force_scale(float scale) { forced_scale_ = scale; }

  bool shows(const ViewKey& key) const { return has_frame_ && shown_key_ == key; }
  bool complete(const ViewKey& key) const { return shows(key) && shown_.scale == 1.0f; }
  unsigned texture() const { return texture_; }
  const PanelFrame& shown() const { return shown_; }  // its rgba is released once uploaded
  PanelModel& model() { return model_; }
  std::uint64_t frames_shown() const { return frames_shown_; }
  double frames_per_second() const { return frames_per_second_; }  // new frames shown, smoothed
  // Whether the panel waits on its worker or has a frame to ask for: the window should keep
  // its loop turning rather than sleep until the next input.
  bool working() const { return !worker_.idle(); }

 private:
  PanelModel& model_;
  ResolutionPolicy policy_;
  RenderWorker worker_;
  unsigned texture_ = 0;
  bool has_frame_ = false;
  float forced_scale_ = 0;
  PanelFrame shown_;
  ViewKey shown_key_, requested_key_;
  std::uint64_t next_id_ = 1, frames_shown_ = 0;
  double frames_per_second_ = 0;
  std::chrono::steady_clock::time_point last_shown_;
};

}  // namespace splat::viewer
