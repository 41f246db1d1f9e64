#include "apps/splat-viewer/render_worker.hpp"

#include <algorithm>
#include <cmath>

namespace splat::viewer {

RenderWorker::RenderWorker(PanelModel& model, std::function<void()> finished)
    : model_(model), finished_callback_(std::move(finished)), thread_([this] { run(); }) {}

RenderWorker::~RenderWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  cancel_ = true;
  wake_.notify_all();
  thread_.join();
}

bool RenderWorker::idle() const {
  std::lock_guard lock(mutex_);
  return !busy_ && !pending_;
}

void RenderWorker::request(const RenderRequest& request) {
  {
    std::lock_guard lock(mutex_);
    if (busy_ || pending_) return;
    pending_ = request;
    current_ = request;
    cancel_ = false;
  }
  wake_.notify_one();
}

std::optional<PanelFrame> RenderWorker::take_finished() {
  std::lock_guard lock(mutex_);
  std::optional<PanelFrame> frame = std::move(finished_);
  finished_.reset();
  return frame;
}

void RenderWorker::run() {
  for (;;) {
    RenderRequest request;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || pending_.has_value(); });
      if (stop_) return;
      request = *pending_;
      pending_.reset();
      busy_ = true;
    }
    const int width = std::max(1, int(std::lround(float(request.camera.width) * request.scale)));
    const int height = std::max(1, int(std::lround(float(request.camera.height) * request.scale)));
    const Camera camera = request.scale == 1.0f ? request.camera : request.camera.resized(width, height);
    PanelFrame frame;
    frame.scale = request.scale;
    frame.request_id = request.id;
    const bool done = model_.render(camera, request.settings, cancel_, frame);
    {
      std::lock_guard lock(mutex_);
      if (done) finished_ = std::move(frame);
      busy_ = false;
    }
    if (finished_callback_) finished_callback_();
  }
}

}  // namespace splat::viewer
