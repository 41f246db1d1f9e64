// Images (read_image: PNG through libpng, other formats through OpenImageIO), under a .png
// name as datasets have them; the seeds include a JPEG.
#include "fuzz/fuzz_support.hpp"
#include "splat/data/image_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return splat::fuzz::read_input_as("image.png", data, size, [](const auto& f) { splat::read_image(f); });
}
