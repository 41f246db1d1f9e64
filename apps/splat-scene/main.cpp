// splat-scene render SCENE --out DIR [--threads N]: ray-traces a scene spec's glTF with
// Embree into a Blender / NeRF-synthetic dataset with exact depth (scenes/src/dataset_writer).
#include <chrono>
#include <cstdio>
#include <memory>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "apps/common/thread_limit.hpp"
#include "splat/raytrace/dataset_writer.hpp"
#include "splat/raytrace/gltf_mesh.hpp"
#include "splat/raytrace/scene_spec.hpp"
#include "splat/core/error.hpp"

namespace {

constexpr const char* kUsage =
    "usage: splat-scene render SCENE.json --out DIR [--threads N]\n"
    "  renders the scene's orbit views into DIR: transforms_{train,test}.json,\n"
    "  {train,test}/r_K.png (RGBA) and depth/{train,test}/r_K.exr\n";

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv, {"out", "threads"}, {"help"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    const auto& words = args.positionals();
    if (words.size() != 2 || words[0] != "render")
      throw splat::ArgumentError("expected \"render SCENE.json --out DIR\" (see --help)");
    const std::filesystem::path out = args.required("out");
    const auto n = args.integer("threads", splat::cli::kThreadsRange);
    const auto thread_limit = splat::cli::limit_threads(n.value_or(0));
    const auto start = std::chrono::steady_clock::now();
    // Everything that can be wrong with the inputs is found before the output folder exists.
    const splat::raytrace::SceneSpec spec = splat::raytrace::load_scene_spec(words[1]);
    const splat::raytrace::Mesh mesh = splat::raytrace::load_gltf_mesh(spec.gltf);
    std::printf("%s: %zu triangles, %d train + %d test views of %dx%d, %d samples per pixel\n",
                words[1].c_str(), mesh.triangle_count(), spec.cameras.train, spec.cameras.test,
                spec.cameras.width, spec.cameras.height, spec.samples_per_pixel);
    std::fflush(stdout);
    splat::raytrace::write_scene_dataset(spec, mesh, out, [](int done, int total) {
      std::printf("rendered %d/%d views\n", done, total);
      std::fflush(stdout);
    });
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("done in %.1f s: dataset in %s\n", seconds, out.string().c_str());
    return 0;
  });
}
