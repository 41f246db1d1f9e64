#include "splat/eval/comparison_grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

namespace {

void require_same_rgb(const Image& a, const Image& b, const char* what) {
  if (a.channels != 3 || b.channels != 3 || a.width != b.width || a.height != b.height)
    throw ArgumentError(std::string(what) + ": images must be RGB and of one size, got " +
                        std::to_string(a.width) + "x" + std::to_string(a.height) + "x" +
                        std::to_string(a.channels) + " and " + std::to_string(b.width) + "x" +
                        std::to_string(b.height) + "x" + std::to_string(b.channels));
}

}  // namespace

Image error_map(const Image& a, const Image& b) {
  require_same_rgb(a, b, "error map");
  Image map(a.width, a.height, 3);
  for (std::size_t p = 0; p < a.pixel_count(); ++p) {
    float sum = 0;
    for (int c = 0; c < 3; ++c) sum += std::abs(a.data[p * 3 + c] - b.data[p * 3 + c]);
    const float shown = std::min(1.0f, kErrorMapGain * sum / 3.0f);
    for (int c = 0; c < 3; ++c) map.data[p * 3 + c] = shown;
  }
  return map;
}

Image concatenate_horizontally(const std::vector<const Image*>& panels) {
  if (panels.empty()) return Image();
  const Image& first = *panels.front();
  for (const Image* panel : panels) require_same_rgb(first, *panel, "comparison grid");
  const int w = first.width;
  Image out(w * int(panels.size()), first.height, 3);
  for (std::size_t i = 0; i < panels.size(); ++i)
    for (int y = 0; y < first.height; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c)
          out.at(int(i) * w + x, y, c) = std::clamp(panels[i]->at(x, y, c), 0.0f, 1.0f);
  return out;
}

Image comparison_grid(const Image& truth, const std::vector<const Image*>& renders) {
  std::vector<Image> errors;
  errors.reserve(renders.size());  // the panels point into it
  std::vector<const Image*> panels = {&truth};
  for (const Image* render : renders) {
    panels.push_back(render);
    errors.push_back(error_map(*render, truth));
  }
  for (const Image& error : errors) panels.push_back(&error);
  return concatenate_horizontally(panels);
}

}  // namespace splat
