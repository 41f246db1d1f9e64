#include "splat/train/validation_views.hpp"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_access.hpp>
#include <numeric>

namespace splat {
namespace {

constexpr std::size_t kNeighbours = 3;  // the views a held-out one keeps in training around it

// The camera's viewing direction in world coordinates: its z axis.
glm::vec3 viewing_direction(const Camera& camera) { return glm::row(camera.camera_from_world_rotation, 2); }

}  // namespace

float view_distance(const Camera& a, const Camera& b, const glm::vec3& scene_center) {
  const glm::vec3 ca = a.center_in_world(), cb = b.center_in_world();
  const float nearer = std::min(glm::distance(ca, scene_center), glm::distance(cb, scene_center));
  const float apart = glm::distance(ca, cb);
  const float along = apart > 0 ? apart / std::max(nearer, 1e-6f) : 0.0f;
  const float cosine = glm::clamp(glm::dot(viewing_direction(a), viewing_direction(b)), -1.0f, 1.0f);
  return along + std::acos(cosine);
}

std::vector<std::size_t> choose_validation_views(const std::vector<DatasetView>& train, const PointCloud& points,
                                                 int every) {
  const std::size_t n = train.size();
  if (every <= 0 || n < 2) return {};
  const glm::vec3 center = scene_centre(train, &points);

  // Each view's others, nearest first (ties to the lower index).
  std::vector<std::vector<std::size_t>> nearest(n);
  std::vector<float> nearest_distance(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::pair<float, std::size_t>> others;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) others.push_back({view_distance(train[i].camera, train[j].camera, center), j});
    std::sort(others.begin(), others.end());
    nearest_distance[i] = others.front().first;
    for (std::size_t k = 0; k < std::min(kNeighbours, others.size()); ++k) nearest[i].push_back(others[k].second);
  }

  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return nearest_distance[a] < nearest_distance[b]; });

  const std::size_t wanted = (n + std::size_t(every) - 1) / std::size_t(every);
  std::vector<std::size_t> taken;
  std::vector<bool> blocked(n, false);
  for (std::size_t i : order) {
    if (taken.size() == wanted) break;
    if (blocked[i]) continue;
    taken.push_back(i);
    blocked[i] = true;
    for (std::size_t j : nearest[i]) blocked[j] = true;
    for (std::size_t j = 0; j < n; ++j)
      if (std::find(nearest[j].begin(), nearest[j].end(), i) != nearest[j].end()) blocked[j] = true;
  }
  std::sort(taken.begin(), taken.end());
  return taken;
}

}  // namespace splat
