#pragma once
// What one side of the viewer shows: a splat model drawn by the tile rasterizer or a NeRF
// drawn ray by ray, behind one interface so the window code treats both alike.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "splat/core/camera.hpp"
#include "splat/raster/rasterizer.hpp"

namespace splat::viewer {

struct ViewSettings {
  int sh_degree = 3;
  float background[3] = {1, 1, 1};
};

// A rendered frame, ready to upload: 8-bit RGBA rows top to bottom.
struct PanelFrame {
  int width = 0, height = 0;   // of this image (the panel's size × scale)
  float scale = 1;             // of the panel's full resolution
  std::vector<std::uint8_t> rgba;
  double render_ms = 0;        // the whole render, conversion included
  RenderTimings timings;       // the rasterizer's stages (splat models)
  std::uint64_t request_id = 0;
};

class PanelModel {
 public:
  virtual ~PanelModel() = default;
  virtual std::string description() const = 0;  // "50,000 Gaussians, SH degree 3"
  virtual std::size_t gaussian_count() const = 0;  // 0 for a NeRF
  virtual int max_sh_degree() const = 0;           // 0 for a NeRF
  virtual bool progressive() const = 0;            // slow: refine over several frames
  // Points to frame the view on (Gaussian means; the NeRF's box corners), [P, 3].
  virtual std::vector<float> framing_points() const = 0;
  // Renders `camera` (already at the frame's resolution) into `frame`. Returns false, with
  // the frame incomplete, once `cancel` is set (checked where the renderer can stop).
  virtual bool render(const Camera& camera, const ViewSettings& settings, const std::atomic<bool>& cancel,
                      PanelFrame& frame) = 0;
};

// Loads a .ply (3DGS) or .nerf model. Throws InputError naming the file when it is missing,
// of another kind, or malformed.
std::unique_ptr<PanelModel> load_panel_model(const std::filesystem::path& file);

// 8-bit RGBA of a float RGB image, each value clamped to [0, 1] and rounded as write_png does.
void to_rgba8(const Image& image, std::vector<std::uint8_t>& rgba);

}  // namespace splat::viewer
