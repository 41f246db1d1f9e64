#include "splat/core/camera.hpp"

namespace splat {

Camera camera_from_blender(const float m[4][4], float fx, float fy, float cx, float cy, int width,
                           int height) {
  // world_from_camera in OpenCV axes: negate the y and z columns of the GL rotation.
  glm::mat3 world_from_camera_rotation;  // glm is column-major: [col][row]
  for (int row = 0; row < 3; ++row) {
    world_from_camera_rotation[0][row] = m[row][0];
    world_from_camera_rotation[1][row] = -m[row][1];
    world_from_camera_rotation[2][row] = -m[row][2];
  }
  const glm::vec3 camera_center(m[0][3], m[1][3], m[2][3]);
  Camera cam;
  cam.camera_from_world_rotation = glm::transpose(world_from_camera_rotation);
  cam.camera_from_world_translation = -(cam.camera_from_world_rotation * camera_center);
  cam.fx = fx; cam.fy = fy; cam.cx = cx; cam.cy = cy;
  cam.width = width; cam.height = height;
  return cam;
}

}  // namespace splat
