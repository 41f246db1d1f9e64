#include "apps/splat-viewer/overlay.hpp"

#include <imgui.h>

namespace splat::viewer {

namespace {

void stats_window(PanelView& panel, int index, float x, const OverlayState& state) {
  ImGui::SetNextWindowPos(ImVec2(x + 8, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.6f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                 ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                 ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs;
  const std::string name = "stats" + std::to_string(index);
  ImGui::Begin(name.c_str(), nullptr, flags);
  const PanelFrame& f = panel.shown();
  ImGui::TextUnformatted(panel.model().description().c_str());
  ImGui::Text("frame %.1f ms at %dx%d (scale %.2f)", f.render_ms, f.width, f.height, f.scale);
  if (panel.model().gaussian_count() > 0)
    ImGui::Text("  project %.1f  bin+sort %.1f  blend %.1f ms", f.timings.project_ms, f.timings.bin_sort_ms,
                f.timings.blend_ms);
  else
    ImGui::TextUnformatted(f.scale < 1.0f ? "  refining..." : "  full resolution");
  ImGui::Text("SH degree %d of %d", std::min(state.sh_degree, panel.model().max_sh_degree()),
              panel.model().max_sh_degree());
  if (panel.frames_shown() > 1) {
    ImGui::SameLine();
    ImGui::Text("  %.1f new frames/s", panel.frames_per_second());
  }
  if (index == 0) {
    if (state.dataset_views > 0) {
      if (state.dataset_view >= 0)
        ImGui::Text("dataset view %d of %d", state.dataset_view, state.dataset_views);
      else
        ImGui::Text("free camera ([ ] for dataset views)");
    }
    ImGui::TextUnformatted(state.message ? state.message : "H: help");
  }
  ImGui::End();
}

void help_window() {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("splat-viewer help (H to close)", nullptr,
               ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse);
  const char* lines[][2] = {{"left drag", "orbit"},
                            {"right / middle drag", "pan"},
                            {"scroll", "zoom"},
                            {"W A S D, Q E", "fly forward, left, back, right, down, up"},
                            {"R", "reset the view"},
                            {"[  ]", "previous / next dataset view (--cameras)"},
                            {"+  -", "SH degree up / down"},
                            {"B", "background white / black"},
                            {"P", "screenshot to splat-viewer-<time>.png"},
                            {"H", "this help"},
                            {"Esc", "quit"}};
  for (const auto& line : lines) {
    ImGui::TextUnformatted(line[0]);
    ImGui::SameLine(170);
    ImGui::TextUnformatted(line[1]);
  }
  ImGui::Separator();
  ImGui::TextWrapped("While the camera moves, frames render at reduced resolution to hold the frame rate; "
                     "they refine to full resolution when it stops (a NeRF over several frames).");
  ImGui::End();
}

}  // namespace

void draw_overlay(std::vector<PanelView*>& panels, int panel_width, const OverlayState& state) {
  for (std::size_t i = 0; i < panels.size(); ++i) stats_window(*panels[i], int(i), float(i) * float(panel_width), state);
  if (state.help) help_window();
}

}  // namespace splat::viewer
