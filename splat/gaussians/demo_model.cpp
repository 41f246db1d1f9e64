#include "splat/gaussians/demo_model.hpp"

#include <cmath>
#include <glm/glm.hpp>
#include <random>

#include "splat/core/spherical_harmonics.hpp"

namespace splat {

namespace {

constexpr float kPi = 3.14159265358979f;

// SH DC coefficient that renders as `rgb` (colour = C0·dc + 0.5).
glm::vec3 dc_for_color(const glm::vec3& rgb) { return (rgb - 0.5f) / float(kShC0); }

// Quaternion (w, x, y, z) turning the Gaussian's local z axis onto `normal`, so a Gaussian
// thin along z lies flat on the surface.
// The half-way construction: q = (1 + z·n, z × n), normalised; undefined for n = −z, where
// any half turn about an axis in the xy plane does.
glm::vec4 quat_facing(const glm::vec3& normal) {
  const glm::vec3 n = glm::normalize(normal);
  if (n.z < -0.9999f) return {0.0f, 1.0f, 0.0f, 0.0f};
  return glm::normalize(glm::vec4(1.0f + n.z, -n.y, n.x, 0.0f));
}

// Rotation about the x axis.
glm::vec3 tilt_about_x(const glm::vec3& v, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return {v.x, c * v.y - s * v.z, s * v.y + c * v.z};
}

void set_gaussian(GaussianModel& m, std::size_t i, const glm::vec3& position,
                  const glm::vec3& normal, float size, float thickness, const glm::vec3& rgb,
                  float shine) {
  for (int a = 0; a < 3; ++a) m.means[3 * i + a] = position[a];
  m.log_scales[3 * i + 0] = std::log(size);
  m.log_scales[3 * i + 1] = std::log(size);
  m.log_scales[3 * i + 2] = std::log(thickness);
  const glm::vec4 q = quat_facing(normal);
  for (int a = 0; a < 4; ++a) m.quats[4 * i + a] = q[a];
  m.opacity_logits[i] = 3.0f;  // opacity 0.95
  const int k = m.sh_coefficients();
  const glm::vec3 dc = dc_for_color(rgb);
  for (int c = 0; c < 3; ++c) m.sh[(i * k) * 3 + c] = dc[c];
  // A little view dependence along the normal (band 1, z-like term): brighter when seen
  // from the side the surface faces.
  for (int c = 0; c < 3; ++c) {
    m.sh[(i * k + 1) * 3 + c] = -shine * normal.y;
    m.sh[(i * k + 2) * 3 + c] = shine * normal.z;
    m.sh[(i * k + 3) * 3 + c] = -shine * normal.x;
  }
}

}  // namespace

GaussianModel make_demo_model(int gaussian_count, unsigned seed) {
  GaussianModel m;
  m.sh_degree = 1;
  m.resize(std::size_t(gaussian_count));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const int sphere_count = gaussian_count * 3 / 4;
  for (int i = 0; i < gaussian_count; ++i) {
    if (i < sphere_count) {
      // Uniform on the unit sphere; eight longitude stripes, alternating with latitude.
      const float z = 2.0f * uniform(rng) - 1.0f, phi = 2.0f * kPi * uniform(rng);
      const float r = std::sqrt(1.0f - z * z);
      const glm::vec3 n(r * std::cos(phi), r * std::sin(phi), z);
      const int stripe = int(phi / (2 * kPi) * 8) + int((z + 1.0f) * 3.0f);
      const glm::vec3 rgb = stripe % 2 ? glm::vec3(0.9f, 0.35f, 0.1f) : glm::vec3(0.15f, 0.4f, 0.85f);
      set_gaussian(m, i, n, n, 0.035f, 0.004f, rgb, 0.15f);
    } else {
      // A flat ring around the equator, tilted, shading from green to yellow.
      const float phi = 2.0f * kPi * uniform(rng), radius = 1.5f + 0.35f * uniform(rng);
      constexpr float kTilt = 0.4f;
      const glm::vec3 p = tilt_about_x({radius * std::cos(phi), radius * std::sin(phi), 0.0f}, kTilt);
      const glm::vec3 n = tilt_about_x({0.0f, 0.0f, 1.0f}, kTilt);
      const float t = (radius - 1.5f) / 0.35f;
      set_gaussian(m, i, p, n, 0.03f, 0.003f, glm::mix(glm::vec3(0.2f, 0.7f, 0.3f), glm::vec3(0.95f, 0.85f, 0.2f), t), 0.0f);
    }
  }
  return m;
}

}  // namespace splat
