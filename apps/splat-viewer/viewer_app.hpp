#pragma once
// The splat-viewer window: GLFW, OpenGL 2 (which Mesa's software renderer also gives) and
// Dear ImGui for the overlay. Each panel's CPU renders arrive from its RenderWorker and are
// shown as a texture; the camera, keys and overlay live here.
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "apps/splat-viewer/panel_model.hpp"
#include "splat/data/transforms_json.hpp"

namespace splat::viewer {

struct ViewerOptions {
  std::vector<std::filesystem::path> files;      // one or two models, side by side
  std::vector<CameraFrame> cameras;              // --cameras: the views [ and ] step through
  int view = 0;                                  // --view K: the view to start from
  int width = 800, height = 600;                 // one panel, in pixels
  ViewSettings settings;
  std::optional<std::filesystem::path> screenshot;  // draw the view, save it, exit
  bool screenshot_overlay = false;               // include the overlay in --screenshot
  bool show_help = false;                        // start with the help open
  double bench_seconds = 0;                      // > 0: the orbit benchmark, then exit
  double target_fps = 30;                        // what reduced resolution aims to hold
};

class WatchedModel;

// Opens the window and runs until it is closed (or the screenshot / benchmark is done).
// `models` are loaded already, one per file. Returns the exit status; Error when no window
// can be opened (no display). With `watched` (--watch; it is models[0]), the window looks for
// a newer model twice a second and shows it.
int run_viewer(const ViewerOptions& options, std::vector<std::unique_ptr<PanelModel>> models,
               WatchedModel* watched = nullptr);

}  // namespace splat::viewer
