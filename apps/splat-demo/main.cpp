// splat-demo --out DIR [--gaussians N] [--views K] [--size PX]
// Writes the built-in procedural model (DIR/model.ply) and an orbit of cameras around it
// (DIR/cameras.json), ready for splat-render and splat-viewer.
#include <cstdio>
#include <string>
#include <vector>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "splat/core/error.hpp"
#include "splat/data/orbit_cameras.hpp"
#include "splat/gaussians/demo_model.hpp"
#include "splat/gaussians/ply_io.hpp"

namespace {

constexpr const char* kUsage = R"(usage: splat-demo --out DIR [--gaussians N] [--views K] [--size PX]

Writes the built-in demo model, a striped sphere circled by a ring, as DIR/model.ply, and
K cameras orbiting it as DIR/cameras.json (Blender transforms format).
  --gaussians N   number of Gaussians (default 20000)
  --views K       number of orbit cameras (default 8)
  --size PX       image width and height of the cameras (default 400)
)";

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv, {"out", "gaussians", "views", "size"}, {"help"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    const std::filesystem::path out = args.required("out");
    const int gaussians = args.integer("gaussians", {1, 10000000}).value_or(20000);
    const int views = args.integer("views", {1, 1000}).value_or(8);
    const int size = args.integer("size", splat::cli::kImageSideRange).value_or(400);
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (!std::filesystem::is_directory(out))
      throw splat::InputError(out, "cannot create the output folder");

    splat::write_ply(splat::make_demo_model(gaussians), out / "model.ply");
    splat::OrbitRig rig;
    rig.count = views;
    rig.radius = 5.5f;
    rig.width = rig.height = size;
    std::vector<std::string> names;
    for (int i = 0; i < views; ++i) names.push_back("./views/view_" + std::to_string(i));
    splat::write_transforms(out / "cameras.json", splat::orbit_cameras(rig), names);
    std::printf("wrote %s and %s\n", (out / "model.ply").string().c_str(),
                (out / "cameras.json").string().c_str());
    return 0;
  });
}
