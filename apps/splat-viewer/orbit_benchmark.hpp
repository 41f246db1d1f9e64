#pragma once
// splat-viewer --bench-orbit: the camera orbits steadily while the window runs as usual, in
// three phases of S seconds each: full resolution, half resolution, and the adaptive policy.
// A phase's rate is the new frames of its own scale shown per second (what the user sees
// move), with their median render time and scale. The first frame is a warm-up.
#include <chrono>
#include <string>
#include <vector>

#include "apps/splat-viewer/panel_view.hpp"

namespace splat::viewer {

class OrbitBenchmark {
 public:
  OrbitBenchmark(double seconds_per_phase, std::vector<PanelView*> panels);

  // Call once per window frame, after the panels updated. Returns true when the last phase
  // has ended; result_json() then holds the figures.
  bool frame();
  // {"width", "height", "panels", "seconds_per_phase", "full": {...}, "half": {...},
  //  "adaptive": {...}} with each phase's fps, render_ms_median, scale_median, frames.
  std::string result_json(int width, int height) const;

 private:
  struct Phase {
    const char* name = "";
    float scale = 0;  // 0: the adaptive policy
    std::chrono::steady_clock::time_point start;
    double fps = 0;
    std::vector<double> render_ms, scales;
  };
  void start_phase();

  double seconds_;
  std::vector<PanelView*> panels_;
  std::vector<Phase> phases_;
  std::size_t phase_ = 0;
  bool started_ = false;
  std::uint64_t last_counted_ = 0;
};

}  // namespace splat::viewer
