#include "splat/raytrace/shading.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace splat::raytrace {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
// Shadow rays start this far (relative to the scene's coordinates' magnitude) off the surface,
// so a surface does not shadow itself through rounding.
constexpr float kShadowOffset = 1e-4f;

int wrap(int i, int n) {
  const int m = i % n;
  return m < 0 ? m + n : m;
}

// Cook–Torrance GGX specular BRDF D·G·F / (4 n·l n·v); the caller multiplies by n·l.
glm::vec3 ggx_specular(const glm::vec3& n, const glm::vec3& v, const glm::vec3& l,
                       const glm::vec3& f0, float roughness) {
  const glm::vec3 h = glm::normalize(v + l);
  const float n_dot_l = std::max(glm::dot(n, l), 0.0f);
  const float n_dot_v = std::max(glm::dot(n, v), 1e-4f);
  const float n_dot_h = std::max(glm::dot(n, h), 0.0f);
  const float v_dot_h = std::max(glm::dot(v, h), 0.0f);
  // α = roughness², kept away from 0 so a mirror-smooth material stays finite.
  const float alpha = std::max(roughness * roughness, 1e-3f);
  const float a2 = alpha * alpha;
  const float d_denominator = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
  const float distribution = a2 / (kPi * d_denominator * d_denominator);
  const float k = alpha * 0.5f;  // Smith–Schlick fitted to GGX
  const float visibility = 1.0f / ((n_dot_l * (1.0f - k) + k) * (n_dot_v * (1.0f - k) + k));
  const glm::vec3 fresnel = f0 + (glm::vec3(1.0f) - f0) * std::pow(1.0f - v_dot_h, 5.0f);
  return fresnel * (distribution * visibility * 0.25f);
}

}  // namespace

glm::vec4 sample_texture(const Texture& texture, glm::vec2 uv) {
  const float x = uv.x * float(texture.width) - 0.5f;
  const float y = uv.y * float(texture.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float wx = x - fx, wy = y - fy;
  const int x0 = wrap(int(fx), texture.width), x1 = wrap(int(fx) + 1, texture.width);
  const int y0 = wrap(int(fy), texture.height), y1 = wrap(int(fy) + 1, texture.height);
  auto at = [&](int xi, int yi) { return texture.texels[std::size_t(yi) * texture.width + xi]; };
  return (1 - wy) * ((1 - wx) * at(x0, y0) + wx * at(x1, y0)) +
         wy * ((1 - wx) * at(x0, y1) + wx * at(x1, y1));
}

glm::vec3 shade(const Mesh& mesh, const RayTracer& tracer, const Lighting& lighting,
                const RayHit& hit, const glm::vec3& origin, const glm::vec3& direction) {
  const std::uint32_t* tri = &mesh.indices[3 * std::size_t(hit.triangle)];
  const float w0 = 1.0f - hit.u - hit.v;
  const glm::vec3& p0 = mesh.positions[tri[0]];
  const glm::vec3& p1 = mesh.positions[tri[1]];
  const glm::vec3& p2 = mesh.positions[tri[2]];
  const glm::vec3 point = origin + hit.t * direction;
  const glm::vec3 view = -direction;

  // Both normals face the viewer: our scenes may contain open or single-sided surfaces.
  glm::vec3 face = glm::cross(p1 - p0, p2 - p0);
  face = glm::length(face) > 0 ? glm::normalize(face) : -direction;
  if (glm::dot(face, view) < 0) face = -face;
  glm::vec3 normal = w0 * mesh.normals[tri[0]] + hit.u * mesh.normals[tri[1]] + hit.v * mesh.normals[tri[2]];
  normal = glm::length(normal) > 1e-12f ? glm::normalize(normal) : face;
  if (glm::dot(normal, view) < 0) normal = -normal;

  const Material& material = mesh.materials[mesh.triangle_material[hit.triangle]];
  glm::vec3 base = glm::vec3(material.base_color);
  if (material.texture >= 0) {
    const glm::vec2 uv = w0 * mesh.uvs[tri[0]] + hit.u * mesh.uvs[tri[1]] + hit.v * mesh.uvs[tri[2]];
    base *= glm::vec3(sample_texture(mesh.textures[material.texture], uv));
  }
  const float metallic = std::clamp(material.metallic, 0.0f, 1.0f);
  const float roughness = std::clamp(material.roughness, 0.0f, 1.0f);
  const glm::vec3 diffuse = base * ((1.0f - metallic) / kPi);
  const glm::vec3 f0 = glm::mix(glm::vec3(0.04f), base, metallic);

  const float scale = std::max({1.0f, std::abs(point.x), std::abs(point.y), std::abs(point.z)});
  const glm::vec3 shadow_origin = point + face * (kShadowOffset * scale);
  glm::vec3 radiance = lighting.ambient * base;
  for (const LightSpec& light : lighting.lights) {
    glm::vec3 to_light;
    float distance;
    glm::vec3 incoming = light.color * light.intensity;
    if (light.type == LightSpec::Type::directional) {
      to_light = -light.direction;
      distance = 1e30f;
    } else {
      to_light = light.position - point;
      distance = glm::length(to_light);
      if (distance <= 0) continue;
      to_light /= distance;
      incoming /= distance * distance;
    }
    const float n_dot_l = glm::dot(normal, to_light);
    // Light from behind the geometric face cannot reach the visible side.
    if (n_dot_l <= 0 || glm::dot(face, to_light) <= 0) continue;
    if (tracer.occluded(shadow_origin, to_light, 0.0f, distance)) continue;
    radiance += (diffuse + ggx_specular(normal, view, to_light, f0, roughness)) * incoming * n_dot_l;
  }
  return radiance;
}

}  // namespace splat::raytrace
