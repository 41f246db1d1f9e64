#include "apps/splat-viewer/viewer_app.hpp"

#define GLFW_INCLUDE_NONE
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl2.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "apps/splat-viewer/input.hpp"
#include "apps/splat-viewer/orbit_benchmark.hpp"
#include "apps/splat-viewer/overlay.hpp"
#include "apps/splat-viewer/panel_view.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "apps/splat-viewer/view_controller.hpp"
#include "apps/splat-viewer/watched_model.hpp"

namespace splat::viewer {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The last error GLFW reported before the window opened, and whether it has.
std::string g_glfw_error;
bool g_window_open = false;

std::string glfw_reason(const std::string& otherwise) {
  return g_glfw_error.empty() ? otherwise : "GLFW: " + g_glfw_error;
}

// GLFW and ImGui set up in the constructor and torn down in the destructor, whatever path
// leaves the viewer: no window is ever left behind.
class Window {
 public:
  Window(int width, int height, const std::string& title) {
    // GLFW's reason goes into our one error line (printed by itself, it made two lines);
    // once the window is open, its messages are printed as they come.
    glfwSetErrorCallback([](int, const char* text) {
      if (g_window_open) std::fprintf(stderr, "GLFW: %s\n", text);
      else g_glfw_error = text;
    });
    if (!glfwInit())
      throw Error("cannot open a window: " + glfw_reason("GLFW found no display") +
                  " (set DISPLAY, or run under xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
      glfwTerminate();
      throw Error("cannot open a window: GLFW could not create an OpenGL 2.1 context (" +
                  glfw_reason("no reason given") + ")");
    }
    g_window_open = true;
    glfwMakeContextCurrent(window_);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // nothing written beside the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL2_Init();
  }
  ~Window() {
    ImGui_ImplOpenGL2_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
    g_window_open = false;
  }
  GLFWwindow* get() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

// The framebuffer, bottom row first in GL, as an image top row first.
Image read_framebuffer(int width, int height) {
  std::vector<std::uint8_t> rgba(std::size_t(width) * std::size_t(height) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  Image image(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.at(x, y, c) = float(rgba[(std::size_t(height - 1 - y) * std::size_t(width) + std::size_t(x)) * 4 +
                                       std::size_t(c)]) /
                            255.0f;
  return image;
}

std::string timestamped_name() {
  char name[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(name, sizeof(name), "splat-viewer-%Y%m%d-%H%M%S.png", std::localtime(&now));
  return name;
}

// Where to start: the dataset view asked for, else framed on the first model.
ViewController start_view(const ViewerOptions& options, PanelModel& model) {
  glm::vec3 up(0, 0, 1);
  if (!options.cameras.empty()) {
    // The cameras' mean up (−y in OpenCV axes: row 1 of R, negated).
    glm::vec3 sum(0);
    for (const CameraFrame& f : options.cameras) {
      const glm::mat3& r = f.camera.camera_from_world_rotation;
      sum -= glm::vec3(r[0][1], r[1][1], r[2][1]);
    }
    if (glm::length(sum) > 1e-6f) up = glm::normalize(sum);
  }
  const float fov_y = glm::radians(50.0f);
  const std::vector<float> points = model.framing_points();
  const Framing framing = frame_points(points.data(), points.size() / 3, fov_y);
  ViewController view(framing.center, framing.distance, up, fov_y);
  if (!options.cameras.empty()) view.show_camera(options.cameras[std::size_t(options.view)].camera);
  return view;
}

}  // namespace

int run_viewer(const ViewerOptions& options, std::vector<std::unique_ptr<PanelModel>> models,
               WatchedModel* watched) {
  const int panel_count = int(models.size());
  const int width = options.width, height = options.height;
  Window window(width * panel_count, height,
                "splat-viewer: " + options.files.front().filename().string() +
                    (panel_count > 1 ? " | " + options.files.back().filename().string() : ""));
  GLFWwindow* glfw = window.get();
  glfwSwapInterval(options.bench_seconds > 0 || options.screenshot ? 0 : 1);

  const double target_ms = 1000.0 / options.target_fps;
  std::vector<std::unique_ptr<PanelView>> views;
  std::vector<PanelView*> panels;
  for (auto& model : models) {
    views.push_back(std::make_unique<PanelView>(*model, target_ms, [] { glfwPostEmptyEvent(); }));
    panels.push_back(views.back().get());
  }
  ViewController view = start_view(options, *models.front());
  ViewSettings settings = options.settings;
  OverlayState overlay;
  overlay.sh_degree = settings.sh_degree;
  overlay.white_background = settings.background[0] > 0.5f;
  overlay.dataset_views = int(options.cameras.size());
  overlay.dataset_view = options.cameras.empty() ? -1 : options.view;
  overlay.help = options.show_help;
  std::string message;
  auto last_move = Clock::now() - std::chrono::seconds(10);
  auto last_frame = Clock::now();
  auto last_watch = Clock::now();
  const auto started = Clock::now();
  std::optional<OrbitBenchmark> benchmark;
  if (options.bench_seconds > 0) benchmark.emplace(options.bench_seconds, panels);
  int complete_frames = 0;  // screenshot: frames drawn since the view completed
  bool animating = true;

  while (!glfwWindowShouldClose(glfw)) {
    // Never spin: the renders need the cores. While a worker renders, sleep until it posts
    // its finished frame (an empty event) or input arrives; when idle, turn at once only if
    // something moves by itself (a held fly key, the benchmark's orbit, a screenshot).
    if (std::any_of(panels.begin(), panels.end(), [](PanelView* p) { return p->working(); }))
      glfwWaitEventsTimeout(0.05);
    else if (animating)
      glfwPollEvents();
    else
      glfwWaitEventsTimeout(0.1);
    ImGui_ImplOpenGL2_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const double dt = std::min(0.1, seconds_since(last_frame));
    last_frame = Clock::now();

    InputResult input;
    if (benchmark) {
      view.orbit(4.0f, 0.0f, float(height));  // a steady turn, as a user dragging
      input.moved = true;
    } else if (!options.screenshot) {
      input = apply_input(view, settings, overlay, options.cameras, dt, height);
      if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) glfwSetWindowShouldClose(glfw, 1);
    }
    animating = benchmark || options.screenshot || input.animating;
    if (input.moved) last_move = Clock::now();

    // A running training's newer model (--watch): shown from the next frame on.
    if (watched && seconds_since(last_watch) > 0.5) {
      last_watch = Clock::now();
      if (watched->refresh() || message.empty()) message = "watching: " + watched->status();
    }

    // Each panel: pick up a finished frame, ask for the next.
    const bool moving = seconds_since(last_move) < 0.15;
    const ViewKey key{view.camera(width, height), settings, watched ? watched->version() : 0};
    for (PanelView* p : panels) p->update(key, moving);

    // Draw each panel's texture, then (unless a bare screenshot) the overlay.
    int fb_width = 0, fb_height = 0;
    glfwGetFramebufferSize(glfw, &fb_width, &fb_height);
    glViewport(0, 0, fb_width, fb_height);
    glClearColor(0.1f, 0.1f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    ImDrawList* background = ImGui::GetBackgroundDrawList();
    for (int i = 0; i < panel_count; ++i)
      if (panels[std::size_t(i)]->frames_shown() > 0)
        background->AddImage(reinterpret_cast<ImTextureID>(std::uintptr_t(panels[std::size_t(i)]->texture())),
                             ImVec2(float(i * width), 0), ImVec2(float((i + 1) * width), float(height)));
    if (!options.screenshot || options.screenshot_overlay) {
      overlay.message = message.empty() ? nullptr : message.c_str();
      draw_overlay(panels, width, overlay);
    }
    ImGui::Render();
    ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());

    if (options.screenshot) {
      // A few frames after the view completes, so the overlay has sized itself too.
      const bool complete = std::all_of(panels.begin(), panels.end(), [&](PanelView* p) { return p->complete(key); });
      complete_frames = complete ? complete_frames + 1 : 0;
      if (complete_frames >= 3) {
        write_png(read_framebuffer(fb_width, fb_height), *options.screenshot);
        std::printf("saved %s (%dx%d)\n", options.screenshot->string().c_str(), fb_width, fb_height);
        return 0;
      }
      if (seconds_since(started) > 600)
        throw Error("the view did not finish rendering within 10 minutes; no screenshot written");
    }
    if (input.screenshot) {
      const std::string name = timestamped_name();
      write_png(read_framebuffer(fb_width, fb_height), name);
      message = "saved " + name;
    }
    glfwSwapBuffers(glfw);

    if (benchmark && benchmark->frame()) {
      std::printf("%s\n", benchmark->result_json(width, height).c_str());
      return 0;
    }
  }
  return 0;
}

}  // namespace splat::viewer
