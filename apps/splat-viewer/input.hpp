#pragma once
// The viewer's mouse and keys (read through Dear ImGui's view of GLFW input) applied to the
// camera, the render settings and the overlay.
#include <vector>

#include "apps/splat-viewer/overlay.hpp"
#include "splat/data/transforms_json.hpp"
#include "apps/splat-viewer/view_controller.hpp"

namespace splat::viewer {

struct InputResult {
  bool moved = false;      // the camera changed
  bool animating = false;  // a held key keeps moving it: keep the loop turning
  bool screenshot = false;  // P was pressed
};

// `dt`: seconds since the last frame (flying speed); `height`: the panel's pixels (drag scale).
InputResult apply_input(ViewController& view, ViewSettings& settings, OverlayState& overlay,
                        const std::vector<CameraFrame>& cameras, double dt, int height);

}  // namespace splat::viewer
