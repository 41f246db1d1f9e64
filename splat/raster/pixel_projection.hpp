#pragma once
// Where a Gaussian's centre lands on the image, computed with the official rasterizer's
// arithmetic, rounding for rounding.
//
// Why not simply fx·x/z + cx − 0.5 (project_to_pixel, which the backward pass differentiates
// and which is the same function in exact arithmetic)? The forward pass is discontinuous:
// a Gaussian whose α at a pixel sits within ~1e-4 (relative) of the 1/255 skip threshold is
// blended or skipped depending on the last bits of its pixel position, and a skipped or
// blended Gaussian changes the pixel by up to T/255. On the conformance view, the direct
// formula put 13 pixels more than 1e-4 away from the official image; with this arithmetic
// every pixel is within 1.1e-6 of it.
//
// The official code projects with the float "full projection" matrix (view matrix times
// OpenGL projection), p_hom = M·[p, 1] with the first product rounded and the other two fused
// (the contraction nvcc applies to its a·x + b·y + c·z + d), divides by w + 1e-7, and maps NDC
// to pixels in double: ((ndc + 1)·size − 1) / 2.
#include <cmath>

#include "splat/core/camera.hpp"
#include "splat/core/simd.hpp"
#include "splat/raster/projection_math.hpp"

namespace splat {

class PixelProjection {
 public:
  explicit PixelProjection(const Camera& camera) : width_(camera.width), height_(camera.height) {
    // The projection matrix's x row is (P00, 0, P02, 0) with P00 = 2·fx / width and
    // P02 = 2·cx / width − 1 (zero for a centred principal point, as the official code
    // assumes); likewise y. Rows of the full matrix: P00·(view row 0) + P02·(view row 2).
    const glm::mat3& r = camera.camera_from_world_rotation;  // [column][row]
    const glm::vec3& t = camera.camera_from_world_translation;
    const float p00 = float(2.0 * double(camera.fx) / camera.width);
    const float p02 = float(2.0 * double(camera.cx) / camera.width - 1.0);
    const float p11 = float(2.0 * double(camera.fy) / camera.height);
    const float p12 = float(2.0 * double(camera.cy) / camera.height - 1.0);
    for (int k = 0; k < 3; ++k) {
      x_row_[k] = std::fma(r[k][2], p02, r[k][0] * p00);
      y_row_[k] = std::fma(r[k][2], p12, r[k][1] * p11);
      w_row_[k] = r[k][2];
    }
    x_row_[3] = std::fma(t.z, p02, t.x * p00);
    y_row_[3] = std::fma(t.z, p12, t.y * p11);
    w_row_[3] = t.z;
  }

  Vec2<float> operator()(const glm::vec3& mean_world) const {
    const float x = row_times(x_row_, mean_world), y = row_times(y_row_, mean_world);
    const float inv_w = 1.0f / (row_times(w_row_, mean_world) + 1e-7f);
    return {ndc_to_pixel(x * inv_w, width_), ndc_to_pixel(y * inv_w, height_)};
  }

  // The same for kLanes points at once, each lane rounded exactly as the scalar call.
  void operator()(simd::f32v x, simd::f32v y, simd::f32v z, simd::f32v& pixel_x,
                  simd::f32v& pixel_y) const {
    const simd::f32v inv_w = 1.0f / (row_times(w_row_, x, y, z) + 1e-7f);
    pixel_x = ndc_to_pixel(row_times(x_row_, x, y, z) * inv_w, width_);
    pixel_y = ndc_to_pixel(row_times(y_row_, x, y, z) * inv_w, height_);
  }

 private:
  // a·x + b·y + c·z + d as nvcc evaluates it: fma(c, z, fma(a, x, b·y)) + d.
  static float row_times(const float row[4], const glm::vec3& p) {
    return std::fma(row[2], p.z, std::fma(row[0], p.x, row[1] * p.y)) + row[3];
  }
  static simd::f32v row_times(const float row[4], simd::f32v x, simd::f32v y, simd::f32v z) {
    using simd::broadcast;
    return simd::fma(broadcast(row[2]), z, simd::fma(broadcast(row[0]), x, row[1] * y)) + row[3];
  }
  static float ndc_to_pixel(float ndc, int size) {
    return float(((double(ndc) + 1.0) * size - 1.0) * 0.5);
  }
  static simd::f32v ndc_to_pixel(simd::f32v ndc, int size) {
    const simd::f64v wide = __builtin_convertvector(ndc, simd::f64v);
    return __builtin_convertvector(((wide + 1.0) * double(size) - 1.0) * 0.5, simd::f32v);
  }

  float x_row_[4], y_row_[4], w_row_[4];
  int width_, height_;
};

}  // namespace splat
