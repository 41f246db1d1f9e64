// glTF scenes (load_gltf_mesh), as text .gltf; buffers come inline as data: URIs.
#include "splat/raytrace/gltf_mesh.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("scene.gltf", data, size,
                                    [](const auto& f) { splat::raytrace::load_gltf_mesh(f); });
}
