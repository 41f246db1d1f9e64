#include "splat/core/camera.hpp"

namespace splat {

Camera camera_from_blender(const double m[4][4], float fx, float fy, float cx, float cy, int width,
                           int height) {
  // world_from_camera in OpenCV axes: negate the y and z columns of the GL matrix. It is
  // inverted in double and only then rounded to float, as the official loader does, so the
  // rounding of the view matrix (and of every pixel position after it) is the same as theirs.
  glm::dmat4 world_from_camera;  // glm is column-major: [col][row]
  for (int row = 0; row < 4; ++row) {
    world_from_camera[0][row] = m[row][0];
    world_from_camera[1][row] = -m[row][1];
    world_from_camera[2][row] = -m[row][2];
    world_from_camera[3][row] = m[row][3];
  }
  const glm::dmat4 camera_from_world = glm::inverse(world_from_camera);
  Camera cam;
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row)
      cam.camera_from_world_rotation[col][row] = float(camera_from_world[col][row]);
  for (int row = 0; row < 3; ++row)
    cam.camera_from_world_translation[row] = float(camera_from_world[3][row]);
  cam.fx = fx; cam.fy = fy; cam.cx = cx; cam.cy = cy;
  cam.width = width; cam.height = height;
  return cam;
}

}  // namespace splat
