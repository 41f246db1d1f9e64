// .nerf and .ngp model files (read_nerf; the magic tells them apart).
#include "fuzz/fuzz_support.hpp"
#include "splat/nerf/nerf_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("model.nerf", data, size, [](const auto& f) { splat::read_nerf(f); });
}
