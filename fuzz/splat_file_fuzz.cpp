// .splat web models (read_splat_file; docs/DESIGN.md §4.12).
#include "fuzz/fuzz_support.hpp"
#include "splat/gaussians/splat_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("model.splat", data, size, [](const auto& f) { splat::read_splat_file(f); });
}
