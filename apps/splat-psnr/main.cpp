// splat-psnr A B [--bg COLOUR]: PSNR between two images, or between same-named PNGs of two
// folders (one line per image, then the minimum and mean). Used for the conformance protocol
// (P2): splat-psnr OUT testdata/conformance/reference. With --bg, RGBA images (a dataset's
// test images) are composited onto that background first, as the trainers see them.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/eval/metrics.hpp"

namespace fs = std::filesystem;

namespace {

// Colour channels only: without a background, an alpha channel is not part of the
// picture's PSNR; with one, the picture is what shows over it.
splat::Image rgb_of(const splat::Image& image, const std::optional<std::array<float, 3>>& background) {
  if (image.channels != 4) return image;
  if (background) return splat::composite_onto(image, background->data());
  splat::Image rgb(image.width, image.height, 3);
  for (std::size_t p = 0; p < image.pixel_count(); ++p)
    for (int c = 0; c < 3; ++c) rgb.data[3 * p + c] = image.data[4 * p + c];
  return rgb;
}

double psnr_of_files(const fs::path& a, const fs::path& b,
                     const std::optional<std::array<float, 3>>& background) {
  const splat::Image image_a = rgb_of(splat::read_image(a), background);
  const splat::Image image_b = rgb_of(splat::read_image(b), background);
  const auto shape = [](const splat::Image& i) {
    return std::to_string(i.width) + "x" + std::to_string(i.height) + "x" + std::to_string(i.channels);
  };
  if (image_a.width != image_b.width || image_a.height != image_b.height || image_a.channels != image_b.channels)
    throw splat::InputError(b, "is " + shape(image_b) + " but " + a.string() + " is " + shape(image_a) +
                                   " (after the alpha channel is dropped or composited)");
  return splat::psnr(image_a, image_b);
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv, {"bg"}, {"help"});
    if (args.has("help")) {
      std::fputs("usage: splat-psnr A B [--bg COLOUR]   (two images, or two folders of same-named\n"
                 "       PNGs; --bg composites RGBA images onto that background first:\n"
                 "       white, black or R,G,B in [0, 1])\n",
                 stdout);
      return 0;
    }
    if (args.positionals().size() != 2)
      throw splat::ArgumentError("expected two images or two folders, A and B (see --help)");
    const fs::path a = args.positionals()[0], b = args.positionals()[1];
    const std::optional<std::array<float, 3>> background = args.colour("bg");
    for (const fs::path& input : {a, b})
      if (!fs::exists(input)) throw splat::InputError(input, "does not exist");
    if (fs::is_directory(a) != fs::is_directory(b))
      throw splat::InputError(b, fs::is_directory(a) ? "is not a folder, but " + a.string() + " is"
                                                     : "is a folder, but " + a.string() + " is not");
    if (!fs::is_directory(a)) {
      std::printf("%.3f\n", psnr_of_files(a, b, background));
      return 0;
    }
    std::vector<fs::path> names;
    for (const auto& entry : fs::directory_iterator(a))
      if (entry.path().extension() == ".png") names.push_back(entry.path().filename());
    if (names.empty()) throw splat::InputError(a, "no PNG images in the folder");
    std::sort(names.begin(), names.end());
    double minimum = 1e300, sum = 0;
    for (const fs::path& name : names) {
      if (!fs::exists(b / name)) throw splat::InputError(b / name, "no image of that name to compare with");
      const double db = psnr_of_files(a / name, b / name, background);
      std::printf("%s %.3f dB\n", name.string().c_str(), db);
      minimum = std::min(minimum, db);
      sum += db;
    }
    std::printf("images %zu  min %.3f dB  mean %.3f dB\n", names.size(), minimum, sum / double(names.size()));
    return 0;
  });
}
