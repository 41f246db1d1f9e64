// COLMAP text files: cameras.txt, images.txt, points3D.txt, each reader on the same input.
#include <vector>

#include "fuzz/fuzz_support.hpp"
#include "splat/data/colmap_readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splat;
  using namespace splat::colmap_detail;
  fuzz::read_input_as("cameras.txt", data, size, [](const auto& f) { read_cameras_text(f); });
  fuzz::read_input_as("images.txt", data, size, [](const auto& f) { read_images_text(f); });
  return fuzz::read_input_as("points3D.txt", data, size, [](const auto& f) {
    std::vector<float> positions, colors;
    read_points_text(f, positions, colors);
  });
}
