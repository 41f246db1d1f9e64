#pragma once
// The model training starts from: the dataset's point cloud where it has one, otherwise
// random points placed by what the training views say about the scene (see initial_model).
#include <cstddef>
#include <string>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "splat/data/dataset.hpp"
#include "splat/gaussians/gaussian_model.hpp"
#include "splat/train/training_config.hpp"

namespace splat {

// How the starting model was made, for metrics.json.
struct InitialisationReport {
  // "points" (the point cloud), "cube" (random in a cube: the fixed one of
  // random_init_half_extent, or the one the cameras see) or "frusta" (random in the
  // cameras' view frusta, with a background shell when the images show a background).
  std::string kind;
  glm::vec3 centre{0.0f};       // the cube's centre, or the shell's
  // The cameras' distance from the centre (0 for a point cloud or the fixed cube): the scale
  // the frusta's near and far distances are multiples of.
  float distance = 0;
  float half_extent = 0;        // "cube"
  float near = 0, far = 0;      // "frusta": the distances from the cameras points span
  std::size_t frustum_points = 0, shell_points = 0;
  float shell_radius = 0;
};
nlohmann::json to_json(const InitialisationReport& report);

// A Gaussian budget (max_gaussians) bounds the starting model too. Without a point cloud:
// - random_init_half_extent > 0: random_init_points uniform in the cube [−h, h]³ around the
//   origin (the official Blender recipe, whose objects fit in ±1.3).
// - random_init_half_extent = 0, the scene follows the training cameras (camera_rig.hpp):
//   when their images leave the background out (on average at least half of their frames
//   show the plain colour they were composited onto, DatasetView::frame_background_share:
//   an object on its own) and their axes converge, the cube centred on their focus whose
//   half extent is the radius of the ball every camera sees whole; for an object rig like
//   the Blender scenes' this is about the official cube (lego400: ±1.365 around the origin).
//   Otherwise the scene may reach any distance: the points are drawn through the views,
//   uniformly in disparity, from random_init_near to random_init_far times the cameras'
//   distance D from the focus, each at the depth the other views' colours agree with most
//   of random_init_depth_candidates (view_points.hpp); and when the images show a
//   background (which nothing else would draw: the sky, a far wall)
//   random_init_shell_fraction of them form a background shell on the sphere of radius
//   random_init_far·D round the focus, over the part the views see, coloured as the views
//   see it. Without a focus (parallel or outward axes) D is the cameras' spread (the scene
//   extent) and the centre their mean.
// Everything random is drawn from config.seed. The config is validated first
// (validate(SplatTrainingConfig): ArgumentError naming the setting).
GaussianModel initial_model(const Dataset& dataset, const SplatTrainingConfig& config,
                            InitialisationReport* report = nullptr);

}  // namespace splat
