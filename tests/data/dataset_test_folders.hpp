#pragma once
// Tiny dataset folders written by the tests: Blender folders of RGBA PNGs and COLMAP folders
// (sparse/0 in text or binary form plus images/).
#include <cstdio>
#include <filesystem>
#include <string>

#include "tests/data/colmap_test_writer.hpp"
#include "splat/core/image.hpp"
#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat::test {

// An image whose values are exact 8-bit codes, different for every seed; with 4 channels
// the alpha runs through 0, 1 and values between.
inline Image code_pattern(int width, int height, int channels, int seed) {
  Image image(width, height, channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c) {
        const int code = (x * 37 + y * 91 + c * 53 + seed * 29) % 256;
        image.at(x, y, c) = float(code) / 255.0f;
      }
  if (channels == 4) {
    image.at(0, 0, 3) = 0.0f;
    image.at(1, 0, 3) = 1.0f;
  }
  return image;
}

// transforms JSON with `count` frames named <prefix>_<k> in <folder_name>/, cameras 4 units
// down +z from a point that moves with k (rigid transforms, OpenGL axes).
inline std::string transforms_json(const std::string& folder_name, const std::string& prefix,
                                   int count) {
  std::string frames;
  for (int k = 0; k < count; ++k) {
    if (k) frames += ",";
    frames += R"({"file_path":"./)" + folder_name + "/" + prefix + "_" + std::to_string(k) +
              R"(","transform_matrix":[[1,0,0,)" + std::to_string(0.5 * k) +
              "],[0,1,0," + std::to_string(-0.25 * k) + "],[0,0,1,4],[0,0,0,1]]}";
  }
  return R"({"camera_angle_x":0.8,"frames":[)" + frames + "]}";
}

// A Blender folder with `train` and `test` frames of width x height images with `channels`
// channels; the test split is written as `test_json` (transforms_test.json or _val.json).
inline void write_blender_folder(const std::filesystem::path& dir, int width, int height,
                                 int train, int test, int channels = 4,
                                 const std::string& test_json = "transforms_test.json") {
  std::filesystem::create_directories(dir / "train");
  std::filesystem::create_directories(dir / "test");
  write_text(dir / "transforms_train.json", transforms_json("train", "r", train));
  write_text(dir / test_json, transforms_json("test", "t", test));
  for (int k = 0; k < train; ++k)
    write_png(code_pattern(width, height, channels, k), dir / "train" / ("r_" + std::to_string(k) + ".png"));
  for (int k = 0; k < test; ++k)
    write_png(code_pattern(width, height, channels, 100 + k),
              dir / "test" / ("t_" + std::to_string(k) + ".png"));
}

enum class ModelForm { kText, kBinary };

// A COLMAP folder: the model in sparse/0 and an RGB image of its camera's size for every
// image of the model, seeded by its position in the list.
inline void write_colmap_folder(const std::filesystem::path& dir, const TestModel& model,
                                ModelForm form) {
  if (form == ModelForm::kText)
    write_colmap_text(model, dir / "sparse" / "0");
  else
    write_colmap_binary(model, dir / "sparse" / "0");
  std::filesystem::create_directories(dir / "images");
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    const ColmapImage& image = model.images[i];
    int width = 0, height = 0;
    for (const ColmapCamera& camera : model.cameras)
      if (camera.id == image.camera_id) width = camera.width, height = camera.height;
    write_png(code_pattern(width, height, 3, int(i)), dir / "images" / image.name);
  }
}

}  // namespace splat::test
