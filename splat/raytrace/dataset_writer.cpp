#include "splat/raytrace/dataset_writer.hpp"

#include <string>
#include <vector>

#include "splat/raytrace/orbit_rig.hpp"
#include "splat/raytrace/ray_tracer.hpp"
#include "splat/raytrace/scene_renderer.hpp"
#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/orbit_cameras.hpp"

namespace splat::raytrace {

namespace fs = std::filesystem;

void write_scene_dataset(const SceneSpec& spec, const Mesh& mesh, const fs::path& out,
                         const Progress& progress) {
  const RayTracer tracer(mesh);
  const Lighting lighting{spec.lights, spec.ambient};
  const RenderSettings settings{spec.samples_per_pixel, spec.seed, spec.background};
  const std::vector<Camera> train = orbit_rig_cameras(spec.cameras, Split::train);
  const std::vector<Camera> test = orbit_rig_cameras(spec.cameras, Split::test);
  const int total = int(train.size() + test.size());
  int done = 0;
  unsigned view_id = 0;  // distinct across both splits: it seeds the pixel jitter

  auto write_split = [&](const std::vector<Camera>& cameras, const std::string& split) {
    if (cameras.empty()) return;
    std::error_code ec;
    fs::create_directories(out / split, ec);
    if (!ec) fs::create_directories(out / "depth" / split, ec);
    if (ec) throw InputError(out / split, "cannot create the folder: " + ec.message());
    std::vector<std::string> file_paths;
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      const std::string name = "r_" + std::to_string(i);
      const RenderedView view = render_view(mesh, tracer, lighting, cameras[i], settings, view_id++);
      write_png(view.color, out / split / (name + ".png"), 8);
      write_float_image(view.depth, out / "depth" / split / (name + ".exr"));
      std::string file_path = "./";  // two steps: GCC 12 warns falsely (-Wrestrict) on "lit" + string
      file_path += split + "/" + name;
      file_paths.push_back(file_path);
      if (progress) progress(++done, total);
    }
    write_transforms(out / ("transforms_" + split + ".json"), cameras, file_paths);
  };
  write_split(train, "train");
  write_split(test, "test");
}

}  // namespace splat::raytrace
