#include "apps/splat-viewer/orbit_benchmark.hpp"

#include <algorithm>
#include <cstdio>

namespace splat::viewer {

namespace {

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

OrbitBenchmark::OrbitBenchmark(double seconds_per_phase, std::vector<PanelView*> panels)
    : seconds_(seconds_per_phase), panels_(std::move(panels)) {
  for (const auto& [name, scale] : {std::pair{"full", 1.0f}, {"half", 0.5f}, {"adaptive", 0.0f}}) {
    Phase phase;
    phase.name = name;
    phase.scale = scale;
    phases_.push_back(phase);
  }
}

void OrbitBenchmark::start_phase() {
  Phase& p = phases_[phase_];
  for (PanelView* panel : panels_) panel->force_scale(p.scale);
  p.start = std::chrono::steady_clock::now();
  last_counted_ = panels_[0]->frames_shown();
}

bool OrbitBenchmark::frame() {
  if (phase_ >= phases_.size()) return true;
  PanelView& first = *panels_[0];
  if (!started_) {
    // The first frame (allocations, caches) is a warm-up, not part of any phase.
    if (first.frames_shown() == 0) return false;
    started_ = true;
    start_phase();
    return false;
  }
  Phase& p = phases_[phase_];
  // A frame asked for in the previous phase may arrive in this one: count only this
  // phase's own scale (any scale in the adaptive phase).
  if (first.frames_shown() != last_counted_) {
    last_counted_ = first.frames_shown();
    if (p.scale == 0 || first.shown().scale == p.scale) {
      p.render_ms.push_back(first.shown().render_ms);
      p.scales.push_back(first.shown().scale);
    }
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - p.start).count();
  // A phase lasts at least its seconds and until one frame of its own was shown (a
  // heavily loaded machine may take longer than a short phase for one).
  if (elapsed < seconds_ || p.render_ms.empty()) return false;
  p.fps = double(p.render_ms.size()) / elapsed;
  if (++phase_ == phases_.size()) return true;
  start_phase();
  return false;
}

std::string OrbitBenchmark::result_json(int width, int height) const {
  char text[1024];
  int n = std::snprintf(text, sizeof(text), "{\"width\": %d, \"height\": %d, \"panels\": %zu, \"seconds_per_phase\": %.1f",
                        width, height, panels_.size(), seconds_);
  for (const Phase& p : phases_)
    n += std::snprintf(text + n, sizeof(text) - std::size_t(n),
                       ", \"%s\": {\"fps\": %.2f, \"render_ms_median\": %.2f, \"scale_median\": %.3f, \"frames\": %zu}",
                       p.name, p.fps, median(p.render_ms), median(p.scales), p.render_ms.size());
  std::snprintf(text + n, sizeof(text) - std::size_t(n), "}");
  return text;
}

}  // namespace splat::viewer
