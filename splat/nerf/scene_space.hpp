#pragma once
// Where the NeRF's field lives and how rays sample it.
//
// A bounded scene (an object rendered on its own) is a box: rays sample only inside it, and
// the networks and the occupancy grid see world coordinates.
//
// An unbounded scene (a photograph with its background, content from near the cameras to
// the horizon) keeps the box as its inner region and contracts everything outside it into a
// shell, after Mip-NeRF 360 (Barron et al. 2022, eq. 10) in its L∞ form, which maps boxes to
// boxes so the occupancy grid's cells stay axis-aligned:
//   u = (x − centre) / half_size                (per axis: the box becomes [−1, 1]³)
//   contract(u) = u                      if ‖u‖∞ ≤ 1
//               = (2 − 1/‖u‖∞) · u/‖u‖∞  otherwise        (all space inside [−2, 2]³)
// The networks and the occupancy grid then see contract(u). Along a ray, half the coarse
// samples are spaced evenly in distance up to where the ray leaves the box and half evenly in
// disparity (1/t) from there to kUnboundedFarFactor box sizes away, so the far background
// gets as many samples as the near scene, each covering the same share of the contracted
// shell. The last sample's interval reaches that far distance: whatever a ray meets nowhere
// else, its last sample draws (the sky).
#include <random>
#include <span>

#include <glm/glm.hpp>

#include "splat/core/rays.hpp"

namespace splat {

// How far an unbounded ray samples, in units of the box's largest half-size: contract()
// maps that distance to within 0.001 of the shell's outer face.
constexpr float kUnboundedFarFactor = 1000.0f;

struct SceneSpace {
  AxisAlignedBox box;     // the scene (bounded) or its inner region (unbounded)
  bool unbounded = false;

  // The point the networks and the occupancy grid see for world point `world`.
  glm::vec3 to_network(const glm::vec3& world) const;
  // Where network coordinates lie: the box itself, or [−2, 2]³ when unbounded.
  AxisAlignedBox network_box() const;

  // Places n = t.size() stratified samples on `ray` (jittered from `rng` when `jitter`, else
  // bin midpoints) with their lengths δ, as stratified_samples (samplers.hpp) does: inside the
  // box between max(entry, near) and the exit when bounded; when unbounded, from `near` on, as
  // described above. Returns false (no samples) when a bounded ray misses the box.
  bool place_samples(const Ray& ray, float near, bool jitter, std::mt19937& rng, std::span<float> t,
                     std::span<float> delta) const;
};

}  // namespace splat
