// PLY models (read_ply): the 3DGS layout, ASCII or binary.
#include "fuzz/fuzz_support.hpp"
#include "splat/gaussians/ply_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("model.ply", data, size, [](const auto& f) { splat::read_ply(f); });
}
