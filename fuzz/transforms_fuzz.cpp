// Transforms JSON (load_transforms): cameras of a Blender dataset.
#include "fuzz/fuzz_support.hpp"
#include "splat/data/transforms_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("transforms.json", data, size, [](const auto& f) { splat::load_transforms(f); });
}
