#pragma once
// Radiance leaving a hit point towards the camera: direct light from the spec's directional
// and point lights (with shadow rays), a GGX specular lobe, and a constant ambient term.
#include <vector>

#include <glm/glm.hpp>

#include "splat/raytrace/gltf_mesh.hpp"
#include "splat/raytrace/ray_tracer.hpp"
#include "splat/raytrace/scene_spec.hpp"

namespace splat::raytrace {

// Bilinear lookup with wrap-around (glTF's default sampler, REPEAT), texel centres at
// half-integers; returns linear RGBA.
glm::vec4 sample_texture(const Texture& texture, glm::vec2 uv);

struct Lighting {
  std::vector<LightSpec> lights;
  glm::vec3 ambient{0.0f};
};

// Shading model (why these choices): Lambert diffuse weighted by (1 − metallic) plus a
// Cook–Torrance GGX lobe with α = roughness², Smith–Schlick visibility and Schlick Fresnel
// from F0 = mix(0.04, base colour, metallic), the usual metallic-roughness reading of glTF.
// Ambient adds ambient × base colour (no environment reflections), so a fully metallic
// surface still shows its colour where no light reaches it.
glm::vec3 shade(const Mesh& mesh, const RayTracer& tracer, const Lighting& lighting,
                const RayHit& hit, const glm::vec3& origin, const glm::vec3& direction);

}  // namespace splat::raytrace
