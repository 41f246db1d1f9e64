#pragma once
// Renders one panel's frames on a thread of its own, so the window keeps handling input
// whatever a frame costs. The window asks for a frame when the worker is idle, may cancel a
// slow one (a NeRF refinement the camera has left), and picks up finished frames.
#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

#include "apps/splat-viewer/panel_model.hpp"

namespace splat::viewer {

struct RenderRequest {
  Camera camera;  // at the panel's full resolution
  float scale = 1;
  ViewSettings settings;
  std::uint64_t id = 0;
};

class RenderWorker {
 public:
  // `finished` is called on the worker thread after each frame (the window uses it to wake
  // its event loop: glfwPostEmptyEvent is thread-safe).
  RenderWorker(PanelModel& model, std::function<void()> finished);
  ~RenderWorker();
  RenderWorker(const RenderWorker&) = delete;
  RenderWorker& operator=(const RenderWorker&) = delete;

  bool idle() const;
  // Starts a frame; ignored unless idle().
  void request(const RenderRequest& request);
  // Asks the frame in flight to stop (it is then dropped).
  void cancel() { cancel_ = true; }
  // The frame finished since the last call, if any.
  std::optional<PanelFrame> take_finished();
  // The request in flight or last finished.
  const RenderRequest& current() const { return current_; }

 private:
  void run();

  PanelModel& model_;
  std::function<void()> finished_callback_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<RenderRequest> pending_;
  std::optional<PanelFrame> finished_;
  RenderRequest current_;
  bool busy_ = false, stop_ = false;
  std::atomic<bool> cancel_{false};
  std::thread thread_;  // last: starts once everything above exists
};

}  // namespace splat::viewer
