#include "apps/splat-viewer/input.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>

namespace splat::viewer {

InputResult apply_input(ViewController& view, ViewSettings& settings, OverlayState& overlay,
                        const std::vector<CameraFrame>& cameras, double dt, int height) {
  InputResult result;
  const ImGuiIO& io = ImGui::GetIO();
  // Input over an ImGui window (the help) belongs to it.
  if (!io.WantCaptureMouse) {
    const bool dragged = io.MouseDelta.x != 0 || io.MouseDelta.y != 0;
    if (io.MouseDown[0] && dragged) {
      view.orbit(io.MouseDelta.x, io.MouseDelta.y, float(height));
      result.moved = true;
    }
    if ((io.MouseDown[1] || io.MouseDown[2]) && dragged) {
      view.pan(io.MouseDelta.x, io.MouseDelta.y, float(height));
      result.moved = true;
    }
    if (io.MouseWheel != 0) {
      view.zoom(io.MouseWheel);
      result.moved = true;
    }
  }
  if (io.WantCaptureKeyboard) return result;

  // Flying covers half the viewing distance per second, whatever the scene's scale.
  const float step = float(dt) * 0.5f * view.distance();
  const float forward = float(ImGui::IsKeyDown(GLFW_KEY_W)) - float(ImGui::IsKeyDown(GLFW_KEY_S));
  const float right = float(ImGui::IsKeyDown(GLFW_KEY_D)) - float(ImGui::IsKeyDown(GLFW_KEY_A));
  const float up = float(ImGui::IsKeyDown(GLFW_KEY_E)) - float(ImGui::IsKeyDown(GLFW_KEY_Q));
  if (forward != 0 || right != 0 || up != 0) {
    view.fly(forward * step, right * step, up * step);
    result.moved = result.animating = true;
  }
  if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) {
    view.reset();
    result.moved = true;
  }
  const int count = int(cameras.size());
  const int step_view = int(ImGui::IsKeyPressed(GLFW_KEY_RIGHT_BRACKET)) - int(ImGui::IsKeyPressed(GLFW_KEY_LEFT_BRACKET));
  if (count > 0 && step_view != 0) {
    const int current = overlay.dataset_view >= 0 ? overlay.dataset_view : 0;
    overlay.dataset_view = ((current + step_view) % count + count) % count;
    view.show_camera(cameras[std::size_t(overlay.dataset_view)].camera);
  } else if (result.moved) {
    overlay.dataset_view = -1;
  }
  if (ImGui::IsKeyPressed(GLFW_KEY_EQUAL) || ImGui::IsKeyPressed(GLFW_KEY_KP_ADD))
    settings.sh_degree = std::min(3, settings.sh_degree + 1);
  if (ImGui::IsKeyPressed(GLFW_KEY_MINUS) || ImGui::IsKeyPressed(GLFW_KEY_KP_SUBTRACT))
    settings.sh_degree = std::max(0, settings.sh_degree - 1);
  overlay.sh_degree = settings.sh_degree;
  if (ImGui::IsKeyPressed(GLFW_KEY_B, false)) {
    overlay.white_background = !overlay.white_background;
    for (float& c : settings.background) c = overlay.white_background ? 1.0f : 0.0f;
  }
  if (ImGui::IsKeyPressed(GLFW_KEY_H, false)) overlay.help = !overlay.help;
  result.screenshot = ImGui::IsKeyPressed(GLFW_KEY_P, false);
  return result;
}

}  // namespace splat::viewer
