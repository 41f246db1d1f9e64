#pragma once
// Pinhole camera in the internal convention (docs/DESIGN.md): a world-to-camera rigid
// transform in OpenCV axes (x right, y down, z forward) plus intrinsics in pixels.
// Pixel (i, j) covers [i, i+1] x [j, j+1]; its centre is at (i + 0.5, j + 0.5).
#include <glm/glm.hpp>

namespace splat {

struct Camera {
  glm::mat3 camera_from_world_rotation{1.0f};  // R: x_cam = R * x_world + t
  glm::vec3 camera_from_world_translation{0.0f};  // t
  float fx = 1, fy = 1;  // focal lengths in pixels
  float cx = 0, cy = 0;  // principal point in pixels (image centre: width/2, height/2)
  int width = 0, height = 0;

  // Position of the camera centre in world coordinates: -Rᵀ t.
  glm::vec3 center_in_world() const {
    return -glm::transpose(camera_from_world_rotation) * camera_from_world_translation;
  }
  glm::vec3 camera_from_world(const glm::vec3& p) const {
    return camera_from_world_rotation * p + camera_from_world_translation;
  }
  // tan of half the field of view, as the reference rasterizer derives it from the focal length.
  float tan_half_fov_x() const { return 0.5f * float(width) / fx; }
  float tan_half_fov_y() const { return 0.5f * float(height) / fy; }

  // The same view at another resolution: intrinsics scale with the image.
  Camera resized(int new_width, int new_height) const {
    Camera c = *this;
    const float sx = float(new_width) / float(width), sy = float(new_height) / float(height);
    c.fx *= sx; c.cx *= sx; c.fy *= sy; c.cy *= sy;
    c.width = new_width; c.height = new_height;
    return c;
  }
};

// Builds the internal camera from a Blender / NeRF-synthetic camera-to-world matrix
// (OpenGL axes: x right, y up, looking down -z): flip its y and z axes, then invert.
// `camera_to_world_gl` is row-major as it appears in transforms JSON.
Camera camera_from_blender(const double camera_to_world_gl[4][4], float fx, float fy, float cx,
                           float cy, int width, int height);

}  // namespace splat
