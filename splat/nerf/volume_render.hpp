#pragma once
// The NeRF's volume-rendering step over a batch of rays: densities to α, α composited
// through the shared compositor (ray_composite.hpp), and the backward pass to ∂L/∂σ and
// ∂L/∂rgb per sample.
//
// Rays run in parallel (oneTBB); each ray reads and writes only its own slots, in a fixed
// order, so results are bit-identical for any thread count. Nothing is allocated per ray:
// the result buffers are the caller's and are reused across batches.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace splat {

// The samples of a batch of rays, packed ray after ray (caller-owned).
struct RaySampleBatch {
  // [R + 1] ray r's samples are [ray_offsets[r], ray_offsets[r + 1]).
  std::span<const std::uint32_t> ray_offsets;
  std::span<const float> t;                    // [S] sorted within each ray
  std::span<const float> delta;                // [S] interval lengths (samplers.hpp)

  std::size_t ray_count() const { return ray_offsets.empty() ? 0 : ray_offsets.size() - 1; }
  std::size_t sample_count() const { return t.size(); }
};

// The colour behind the rays: one for the whole batch, or one per ray ([R, 3], stride 3).
// Training on images with transparency draws a random one per ray (nerf_trainer.cpp), so
// that the only way to match a transparent pixel is to leave the ray empty. Converts from
// the one colour, so a caller with one background passes it as before.
struct RayBackgrounds {
  const float* values;
  std::size_t stride = 0;  // 0: every ray shows values[0..3); 3: ray r shows values[3r..3r+3)
  std::size_t colors = 1;  // how many colours `values` holds
  RayBackgrounds(const float* shared) : values(shared) {}  // NOLINT: the common case
  explicit RayBackgrounds(std::span<const float> per_ray)
      : values(per_ray.data()), stride(3), colors(per_ray.size() / 3) {}
  const float* of(std::size_t ray) const { return values + stride * ray; }
};

// Forward results, and what the backward pass reuses (final_transmittance, blended_count,
// sample_alpha).
struct VolumeRenderResult {
  std::vector<float> color;                  // [R, 3] with the background
  std::vector<float> alpha;                  // [R] 1 − final transmittance
  std::vector<float> depth;                  // [R] Σ Tᵢαᵢtᵢ (divide by alpha to normalise)
  std::vector<float> final_transmittance;    // [R] T after the last blended sample
  std::vector<std::uint32_t> blended_count;  // [R] samples blended, a prefix of the ray's list
  std::vector<float> sample_alpha;           // [S] αᵢ = 1 − exp(−σᵢδᵢ)
  std::vector<float> weights;                // [S] Tᵢαᵢ, 0 past the early stop (fine sampling)

  // Sizes every buffer; no allocation when the capacity is already there.
  void resize(std::size_t rays, std::size_t samples);
};

// sigma [S] (≥ 0), rgb [S, 3], backgrounds one or [R, 3]. Throws ArgumentError on
// inconsistent sizes or offsets (offsets[0] = 0, non-decreasing, offsets[R] = S).
void volume_render(const RaySampleBatch& samples, std::span<const float> sigma,
                   std::span<const float> rgb, RayBackgrounds backgrounds,
                   VolumeRenderResult& result);

// Given v_color = ∂L/∂color [R, 3] for the `forward` result of the same inputs (the same
// backgrounds), writes v_sigma [S] and v_rgb [S, 3] (overwritten, not accumulated; zero for
// samples past a ray's early stop). No gradient to t or δ (the sample positions are constants).
void volume_render_backward(const RaySampleBatch& samples, std::span<const float> sigma,
                            std::span<const float> rgb, RayBackgrounds backgrounds,
                            const VolumeRenderResult& forward, std::span<const float> v_color,
                            std::span<float> v_sigma, std::span<float> v_rgb);

}  // namespace splat
