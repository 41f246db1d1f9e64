// make_seed_corpus DIR: writes the binary seeds of the fuzz targets into DIR/<target>/ with
// the project's own writers (and the tests' byte-level PNG and COLMAP writers), so each
// target starts from valid files of every kind it reads. The output is committed as
// fuzz/corpus/; rerun it when a format changes. The text seeds there are written by hand.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/data/colmap_test_writer.hpp"
#include "tests/data/png_bytes.hpp"
#include "splat/gaussians/demo_model.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/gaussians/splat_file.hpp"
#include "splat/gaussians/spz_file.hpp"
#include "splat/nerf/nerf_file.hpp"
#include "fuzz/tiny_training_setup.hpp"

namespace fs = std::filesystem;
using namespace splat;

namespace {

void write_bytes(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << bytes;
}

// The demo model in each web format, at the highest SH degree each holds.
void write_web_model_seeds(const fs::path& splat_dir, const fs::path& spz_dir) {
  fs::create_directories(splat_dir);
  fs::create_directories(spz_dir);
  const GaussianModel model = make_demo_model(3, 1);
  write_splat_file(model, splat_dir / "demo.splat");
  write_spz_file(model, spz_dir / "demo.spz");
}

void write_ply_seeds(const fs::path& dir) {
  fs::create_directories(dir);
  GaussianModel model = make_demo_model(3, 1);
  write_ply(model, dir / "binary_sh3.ply");
  model.sh_degree = 0;
  model.sh.resize(model.size() * 3);
  write_ply(model, dir / "binary_sh0.ply");
  write_bytes(dir / "ascii.ply",
              "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
              "property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\nproperty float opacity\n"
              "property float scale_0\nproperty float scale_1\nproperty float scale_2\nproperty float rot_0\n"
              "property float rot_1\nproperty float rot_2\nproperty float rot_3\nend_header\n"
              "0 0 0 0.1 0.2 0.3 0.5 -2 -2 -2 1 0 0 0\n1 2 3 -0.1 0 0.1 -1 -3 -1 -2 0.5 0.5 0.5 0.5\n");
}

void write_image_seeds(const fs::path& dir, const fs::path& jpeg) {
  std::string grey, rgba16, palette_rows;
  for (int y = 0; y < 4; ++y) {
    grey += '\0' + std::string("\x00\x40\x80\xff", 4);
    rgba16 += '\0' + std::string(4 * 8, '\x7f');
    palette_rows += '\0' + std::string("\x00\x01\x00\x01", 4);
  }
  const std::string palette = test::png_chunk("PLTE", std::string("\x0a\x14\x1e\xc8\x64\x32", 6)) +
                              test::png_chunk("tRNS", std::string("\x80", 1));
  write_bytes(dir / "grey8.png", test::png_file(4, 4, 8, 0, grey));
  write_bytes(dir / "grey1.png", test::png_file(8, 4, 1, 0, std::string("\0\xb2\0\x4d\0\xff\0\x00", 8)));
  write_bytes(dir / "rgba16.png", test::png_file(4, 4, 16, 6, rgba16));
  write_bytes(dir / "palette_trns.png", test::png_file(4, 4, 8, 3, palette_rows, palette));
  std::ifstream in(jpeg, std::ios::binary);
  write_bytes(dir / "small.jpg", std::string(std::istreambuf_iterator<char>(in), {}));
}

void write_nerf_seed(const fs::path& dir) {
  fs::create_directories(dir);
  write_nerf(NerfModel(fuzz::tiny_nerf_config().model, 1), dir / "tiny.nerf");
  write_nerf(NerfModel(fuzz::tiny_ngp_config().model, 1), dir / "tiny.ngp");
}

void write_checkpoint_seeds(const fs::path& dir) {
  fs::create_directories(dir);
  SplatTrainer splat_trainer(fuzz::tiny_dataset(), fuzz::tiny_splat_config());
  for (int i = 0; i < 3; ++i) splat_trainer.step();
  splat_trainer.save_checkpoint(dir / "splat.ckpt");
  NerfTrainer nerf_trainer(fuzz::tiny_dataset(), fuzz::tiny_nerf_config());
  for (int i = 0; i < 3; ++i) nerf_trainer.step();
  nerf_trainer.save_checkpoint(dir / "nerf.ckpt");
  NerfTrainer ngp_trainer(fuzz::tiny_dataset(), fuzz::tiny_ngp_config());
  for (int i = 0; i < 3; ++i) ngp_trainer.step();
  ngp_trainer.save_checkpoint(dir / "ngp.ckpt");
}

// One small model per file kind; the target reads each input as all three kinds.
void write_colmap_binary_seeds(const fs::path& dir) {
  test::TestModel m;
  m.cameras = {{1, ColmapCameraModel::kPinhole, 8, 6, {7.5, 8.25, 4.1, 2.9}},
               {2, ColmapCameraModel::kOpenCv, 8, 6, {7.5, 8, 4, 3, 0.05, -0.01, 0.002, -0.003}}};
  for (int i = 0; i < 2; ++i) {
    ColmapImage image;
    image.id = std::uint32_t(i + 1);
    image.quaternion = test::axis_angle_quaternion(1, 2 - i, 0.5, 0.3 * i + 0.1);
    image.translation = {0.1 * i, -0.2, 3.0 + i};
    image.camera_id = std::uint32_t(i + 1);
    image.name = "image" + std::to_string(i) + ".png";
    m.images.push_back(image);
  }
  for (int i = 0; i < 3; ++i)
    m.points.push_back({{0.125 * i, -0.5 * i, 2.0 + i}, {std::uint8_t(40 * i), 200, std::uint8_t(i)}});
  const fs::path written = dir / "written";
  test::write_colmap_binary(m, written);
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"})
    fs::rename(written / name, dir / name);
  fs::remove_all(written);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_seed_corpus OUT_DIR SMALL_JPEG\n");
    return 2;
  }
  const fs::path out = argv[1];
  write_ply_seeds(out / "ply");
  write_web_model_seeds(out / "splat_file", out / "spz_file");
  write_image_seeds(out / "image", argv[2]);
  write_nerf_seed(out / "nerf_file");
  write_checkpoint_seeds(out / "checkpoint");
  write_colmap_binary_seeds(out / "colmap_binary");
  std::printf("seeds written to %s\n", out.string().c_str());
  return 0;
}
