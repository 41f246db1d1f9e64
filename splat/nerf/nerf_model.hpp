#pragma once
// A trained NeRF: the coarse and fine networks, the box rays sample inside, the occupancy
// grid that lets them skip empty space, and the sampling settings they were trained with
// (rendering must use the same ones). Saved as model.nerf (nerf_file.hpp).
#include <algorithm>
#include <cstdint>
#include <string>

#include "splat/nerf/nerf_mlp.hpp"
#include "splat/nerf/occupancy_grid.hpp"
#include "splat/core/rays.hpp"
#include "splat/core/setting_value.hpp"
#include "splat/nerf/scene_space.hpp"

namespace splat {

// Limits of the settings (docs/DESIGN.md §4.5), checked when a config or a .nerf file is
// read (the networks' own: nerf_mlp.hpp).
constexpr int kMaxNerfSamplesPerRay = 1024;  // coarse (also × render_sample_multiplier), and importance samples
constexpr int kMaxNerfRenderSampleMultiplier = 16;
constexpr float kMaxNerfCoordinate = 1e6f;   // box corners and the near distance

struct NerfSettings {
  // Smaller than the paper's 8×256 networks and 64 + 128 samples: on two CPU cores those
  // train a few hundred iterations in half an hour. The occupancy grid already confines the
  // samples to occupied space, so the coarse network only has to say where in it the surface
  // lies: a small one (2×64) over 64 stratified samples does that for about a sixth of the
  // fine network's cost per sample (15.5k against 92.6k weights). The fine network (4×128) sees the kept coarse positions plus
  // 16 importance samples. In time-matched probes on lego400 (600 s, one thread) these scored
  // 24.39 dB, the other settings tried 22.28–24.21.
  NerfMlpConfig coarse = frequency_mlp_config(10, 4, 2, 64, -1, 32);
  NerfMlpConfig fine = frequency_mlp_config(10, 4, 4, 128, 2, 64);
  int coarse_samples = 64;  // stratified, per ray, before empty space is dropped
  int fine_samples = 16;    // importance-sampled from the coarse weights
  // Renders for evaluation (scores, splat-render, the viewer) place this many times
  // coarse_samples stratified samples: the networks learn the continuous field from jittered
  // samples, and a denser quadrature of it costs no training. lego400, a model of 6,000
  // iterations rendered with 64 → 128 coarse samples: 24.74 → 25.05 dB; trained with 128, at
  // equal time, 24.26 dB. Files without it render with 1.
  int render_sample_multiplier = 2;
  AxisAlignedBox box{glm::vec3(-1.5f), glm::vec3(1.5f)};  // rays sample only inside,
  bool unbounded = false;  // ... or, when unbounded, also beyond it (scene_space.hpp)
  float near = 0.05f;       // no samples closer than this to the camera
  int occupancy_resolution = 64;
  // A grid cell counts as empty when one coarse step through it would be less than this
  // opaque: its optical thickness σ·δ below the value (Instant-NGP's minimum optical
  // thickness), so the density threshold scales with the scene (occupancy_density_threshold).
  // A density threshold of 0.01 regardless of scale kept the transparent start's faint field
  // (σ ≈ 0.05) occupied for thousands of iterations: lego400, 5 minutes on one thread, 1,108
  // iterations and 20.71 dB against 2,646 and 23.17 dB with a threshold near this one's.
  float occupancy_optical_thickness = 0.01f;

  SceneSpace space() const { return {box, unbounded}; }
  // Stratified samples per ray: training's, or an evaluation render's (at most
  // kMaxNerfSamplesPerRay).
  int coarse_samples_for(bool evaluation) const {
    return evaluation ? std::min(coarse_samples * render_sample_multiplier, kMaxNerfSamplesPerRay) : coarse_samples;
  }
  // The length of a coarse step: the box's diagonal over the coarse samples (over half of
  // them when unbounded, where half the samples lie in the box).
  float coarse_step() const;
  // σ below which a cell is empty: occupancy_optical_thickness / coarse_step().
  float occupancy_density_threshold() const { return occupancy_optical_thickness / coarse_step(); }
};

// The settings as the header of a .nerf file and the `model` section of a NeRF config spell
// them (splat/core/settings_table.hpp; older files: nerf_file.cpp).
template <class Table>
void describe_settings(Table& t, NerfSettings& s) {
  const SettingRange coordinate{-kMaxNerfCoordinate, kMaxNerfCoordinate};
  t.section("coarse", s.coarse, read_nerf_mlp_config);
  t.section("fine", s.fine, read_nerf_mlp_config);
  t.number("coarse_samples", s.coarse_samples, {1, kMaxNerfSamplesPerRay});
  t.number("fine_samples", s.fine_samples, {0, kMaxNerfSamplesPerRay});
  t.number("render_sample_multiplier", s.render_sample_multiplier, {1, kMaxNerfRenderSampleMultiplier});
  t.triple("box_min", s.box.lo, coordinate);
  t.triple("box_max", s.box.hi, coordinate);
  t.flag("unbounded", s.unbounded);
  t.number("near", s.near, {0, kMaxNerfCoordinate});
  t.number("occupancy_resolution", s.occupancy_resolution, {1, kMaxOccupancyResolution});
  t.number("occupancy_optical_thickness", s.occupancy_optical_thickness, {0, 1e6});
}

// Throws ArgumentError naming the first setting ("path.key") out of its range, a box that is
// empty on some axis, or a network's bad skip layer.
void validate(const NerfSettings& settings, const std::string& path = "model");

struct NerfModel {
  NerfSettings settings;
  NerfMlp coarse, fine;
  OccupancyGrid grid;

  NerfModel(const NerfSettings& s, std::uint32_t seed)
      : settings(s), coarse(s.coarse, seed, s.space().network_box()), fine(s.fine, seed + 1, s.space().network_box()),
        grid(s.space().network_box(), s.occupancy_resolution, s.occupancy_density_threshold()) {}

  std::size_t parameter_count() const { return coarse.parameter_count() + fine.parameter_count(); }
};

}  // namespace splat
