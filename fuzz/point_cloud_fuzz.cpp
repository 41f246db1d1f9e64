// Point clouds in PLY (read_point_cloud_ply: nerfstudio's sparse_pc.ply; docs/DESIGN.md §4.2).
#include "fuzz/fuzz_support.hpp"
#include "splat/data/point_cloud_ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("sparse_pc.ply", data, size, [](const auto& f) { splat::read_point_cloud_ply(f); });
}
