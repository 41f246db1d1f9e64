// splat-scene's scene specs (load_scene_spec).
#include "splat/raytrace/scene_spec.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("scene.json", data, size,
                                    [](const auto& f) { splat::raytrace::load_scene_spec(f); });
}
