// .spz web models (read_spz_file; docs/DESIGN.md §4.12).
#include "fuzz/fuzz_support.hpp"
#include "splat/gaussians/spz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("model.spz", data, size, [](const auto& f) { splat::read_spz_file(f); });
}
