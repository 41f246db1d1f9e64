// COLMAP binary files: cameras.bin, images.bin, points3D.bin, each reader on the same input.
#include <vector>

#include "fuzz/fuzz_support.hpp"
#include "splat/data/colmap_readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splat;
  using namespace splat::colmap_detail;
  fuzz::read_input_as("cameras.bin", data, size, [](const auto& f) { read_cameras_binary(f); });
  fuzz::read_input_as("images.bin", data, size, [](const auto& f) { read_images_binary(f); });
  return fuzz::read_input_as("points3D.bin", data, size, [](const auto& f) {
    std::vector<float> positions, colors;
    read_points_binary(f, positions, colors);
  });
}
