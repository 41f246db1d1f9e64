#pragma once
// Renders a scene spec's train and test views into a Blender / NeRF-synthetic folder, the
// layout splat::load_dataset reads:
//   transforms_train.json, transforms_test.json   cameras (OpenGL camera-to-world matrices)
//   train/r_K.png, test/r_K.png                    RGBA 8-bit
//   depth/train/r_K.exr, depth/test/r_K.exr        float camera depth, 0 where nothing is hit
// Every file is written through a temporary name and renamed; the transforms of a split are
// written after its images, so a transforms file never names an image that is not there.
// With "test": 0 no test split is written (load_dataset then refuses the folder: it needs one).
#include <filesystem>
#include <functional>

#include "splat/raytrace/gltf_mesh.hpp"
#include "splat/raytrace/scene_spec.hpp"

namespace splat::raytrace {

// Called after each view with (views done, views in total).
using Progress = std::function<void(int done, int total)>;

void write_scene_dataset(const SceneSpec& spec, const Mesh& mesh, const std::filesystem::path& out,
                         const Progress& progress = {});

}  // namespace splat::raytrace
