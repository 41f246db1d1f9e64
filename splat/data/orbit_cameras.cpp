#include "splat/data/orbit_cameras.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"

namespace splat {

Camera look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up, float fx,
               float fy, int width, int height) {
  const glm::vec3 forward = glm::normalize(target - eye);   // camera +z
  const glm::vec3 right = glm::normalize(glm::cross(forward, up));  // camera +x
  const glm::vec3 down = glm::cross(forward, right);        // camera +y
  Camera cam;
  // Rows of camera_from_world are the camera axes in world coordinates (glm: [col][row]).
  for (int col = 0; col < 3; ++col) {
    cam.camera_from_world_rotation[col][0] = right[col];
    cam.camera_from_world_rotation[col][1] = down[col];
    cam.camera_from_world_rotation[col][2] = forward[col];
  }
  cam.camera_from_world_translation = -(cam.camera_from_world_rotation * eye);
  cam.fx = fx;
  cam.fy = fy;
  cam.cx = 0.5f * float(width);
  cam.cy = 0.5f * float(height);
  cam.width = width;
  cam.height = height;
  return cam;
}

std::vector<Camera> orbit_cameras(const OrbitRig& rig) {
  std::vector<Camera> cameras;
  const float focal = 0.5f * float(rig.width) / std::tan(0.5f * rig.fov_x_radians);
  for (int i = 0; i < rig.count; ++i) {
    const float azimuth = 2.0f * 3.14159265358979f * float(i) / float(rig.count);
    const glm::vec3 offset(std::cos(rig.elevation_radians) * std::cos(azimuth),
                           std::cos(rig.elevation_radians) * std::sin(azimuth),
                           std::sin(rig.elevation_radians));
    cameras.push_back(look_at(rig.target + rig.radius * offset, rig.target, glm::vec3(0, 0, 1),
                              focal, focal, rig.width, rig.height));
  }
  return cameras;
}

namespace {

nlohmann::json intrinsics_json(const Camera& camera) {
  return {{"fl_x", camera.fx}, {"fl_y", camera.fy}, {"cx", camera.cx},
          {"cy", camera.cy},   {"w", camera.width},  {"h", camera.height}};
}

}  // namespace

void write_transforms(const std::filesystem::path& file, const std::vector<Camera>& cameras,
                      const std::vector<std::string>& file_paths) {
  if (cameras.empty() || cameras.size() != file_paths.size())
    throw ArgumentError("write_transforms: need one file path per camera, and at least one");
  const Camera& first = cameras.front();
  nlohmann::json doc = intrinsics_json(first);
  doc["camera_angle_x"] = 2.0 * std::atan(0.5 * first.width / first.fx);
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const Camera& cam = cameras[i];
    // world_from_camera in OpenGL axes: the OpenCV axes with y and z negated.
    const glm::mat3 world_from_camera = glm::transpose(cam.camera_from_world_rotation);
    const glm::vec3 center = cam.center_in_world();
    nlohmann::json matrix = nlohmann::json::array();
    for (int row = 0; row < 3; ++row)
      matrix.push_back({world_from_camera[0][row], -world_from_camera[1][row],
                        -world_from_camera[2][row], center[row]});
    matrix.push_back({0.0, 0.0, 0.0, 1.0});
    nlohmann::json frame = {{"file_path", file_paths[i]}, {"transform_matrix", matrix}};
    // A frame whose intrinsics differ from the first's carries its own (one camera per image).
    if (const nlohmann::json own = intrinsics_json(cam); own != intrinsics_json(first)) frame.update(own);
    frames.push_back(frame);
  }
  doc["frames"] = frames;
  write_stream_atomically(file, [&](std::ostream& out) { out << doc.dump(1) << "\n"; });
}

}  // namespace splat
