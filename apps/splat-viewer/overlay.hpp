#pragma once
// The viewer's on-screen text, drawn with Dear ImGui: per panel the model, frame time and
// its stages, resolution scale and SH degree; and the help with every control.
#include <vector>

#include "apps/splat-viewer/panel_view.hpp"

namespace splat::viewer {

struct OverlayState {
  int sh_degree = 3;
  bool white_background = true;
  int dataset_view = -1;        // the dataset view shown, -1 when the camera moved off it
  int dataset_views = 0;
  bool help = false;
  const char* message = nullptr;  // e.g. "saved screenshot.png"
};

void draw_overlay(std::vector<PanelView*>& panels, int panel_width, const OverlayState& state);

}  // namespace splat::viewer
