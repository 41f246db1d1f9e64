#include "splat/raytrace/orbit_rig.hpp"

#include <cmath>
#include <numbers>

#include "splat/data/orbit_cameras.hpp"

namespace splat::raytrace {

std::vector<Camera> orbit_rig_cameras(const OrbitSpec& orbit, Split split) {
  const int count = split == Split::train ? orbit.train : orbit.test;
  const double golden_angle = std::numbers::pi * (3.0 - std::sqrt(5.0));
  const double phase = split == Split::train ? 0.0 : 0.5 * golden_angle;
  const double deg = std::numbers::pi / 180.0;
  // Equal steps in sin(elevation) give equal areas of the band per camera (Archimedes).
  const double z_lo = std::sin(orbit.elevation_lo_deg * deg);
  const double z_hi = std::sin(orbit.elevation_hi_deg * deg);
  const float focal = float(0.5 * orbit.width / std::tan(0.5 * orbit.fov_x_deg * deg));
  std::vector<Camera> cameras;
  cameras.reserve(count);
  for (int i = 0; i < count; ++i) {
    const double z = z_lo + (z_hi - z_lo) * (i + 0.5) / count;
    const double horizontal = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double azimuth = phase + i * golden_angle;
    const glm::vec3 offset(float(horizontal * std::cos(azimuth)), float(z),
                           float(horizontal * std::sin(azimuth)));
    cameras.push_back(look_at(orbit.target + orbit.radius * offset, orbit.target,
                              glm::vec3(0, 1, 0), focal, focal, orbit.width, orbit.height));
  }
  return cameras;
}

}  // namespace splat::raytrace
