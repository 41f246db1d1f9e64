// Every reader consumes its file exactly: a model or checkpoint with bytes after what its
// header declares (a damaged copy, two files concatenated, a writer of another layout) is one
// clean error naming the file, in every format we read (DESIGN §4.4). The PLY reader checks the
// elements it can size: a file ends where its declared rows end, and ASCII files may end in
// blank lines, as editors leave them.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

// `file` with `junk` appended, written to `bad`.
void append(const fs::path& file, const fs::path& bad, const std::string& junk) {
  test::write_text(bad, test::read_file(file) + junk);
}

void expect_clean_error(const test::CommandResult& r, const fs::path& bad, const std::string& expected,
                        const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << what << ": " << r.err;
  EXPECT_EQ(r.err.rfind("error: " + bad.string() + ": ", 0), 0u) << what << ": " << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << what << ": " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ": " << r.err;
}

TEST(TrailingBytes, EveryModelAndCheckpointWithBytesAfterItsDataIsRefusedNamingTheFile) {
  const fs::path dir = test::scratch_dir("trailing_bytes");
  test::write_demo_dataset(dir / "data", 6, 2, 32, 1000);
  test::write_text(dir / "small.json", R"({"random_init_points": 2000})");
  test::write_text(dir / "nerf.json", R"({"rays_per_batch": 64,
    "model": {"coarse": {"depth": 2, "width": 16, "skip_layer": -1, "color_width": 8},
              "fine": {"depth": 2, "width": 16, "skip_layer": -1, "color_width": 8},
              "coarse_samples": 8, "fine_samples": 8}})");
  const std::string data = (dir / "data").string();
  const auto train = [&](const std::string& method, const std::string& config, const fs::path& out,
                         const std::string& extra) {
    return std::string(SPLAT_TRAIN_EXE) + " --method " + method + " --data " + data + " --out " + out.string() +
           " --config " + (dir / config).string() + " --quiet --test-every 0 --threads 1 " + extra;
  };
  ASSERT_EQ(test::run_command(train("splat", "small.json", dir / "splat", "--iters 20 --checkpoint-every 20"), dir)
                .exit_code, 0);
  ASSERT_EQ(test::run_command(train("nerf", "nerf.json", dir / "nerf", "--iters 20 --checkpoint-every 20"), dir)
                .exit_code, 0);
  const fs::path ply = dir / "splat" / "model.ply";
  for (const char* format : {"spz", "splat"})
    ASSERT_EQ(test::run_command(std::string(SPLAT_CONVERT_EXE) + " " + ply.string() + " " +
                                    (dir / (std::string("model.") + format)).string(), dir)
                  .exit_code, 0);
  const std::string cameras = (dir / "data" / "transforms_test.json").string();
  const auto render = [&](const fs::path& model) {
    return std::string(SPLAT_RENDER_EXE) + " --model " + model.string() + " --cameras " + cameras + " --out " +
           (dir / "render").string();
  };

  // Checkpoints, by --resume.
  append(dir / "splat" / "checkpoint.ckpt", dir / "bad_splat.ckpt", "junk");
  expect_clean_error(test::run_command(train("splat", "small.json", dir / "resumed",
                                             "--iters 40 --resume " + (dir / "bad_splat.ckpt").string()), dir),
                     dir / "bad_splat.ckpt", "4 bytes follow the end of the checkpoint", "splat checkpoint");
  append(dir / "nerf" / "checkpoint.ckpt", dir / "bad_nerf.ckpt", std::string(1, '\0'));
  expect_clean_error(test::run_command(train("nerf", "nerf.json", dir / "resumed",
                                             "--iters 40 --resume " + (dir / "bad_nerf.ckpt").string()), dir),
                     dir / "bad_nerf.ckpt", "1 bytes follow the end of the checkpoint", "NeRF checkpoint");
  // Models, by splat-render.
  append(dir / "nerf" / "model.nerf", dir / "bad.nerf", "junk");
  expect_clean_error(test::run_command(render(dir / "bad.nerf"), dir), dir / "bad.nerf", "4 bytes follow the end",
                     ".nerf");
  append(ply, dir / "bad.ply", "junk");
  expect_clean_error(test::run_command(render(dir / "bad.ply"), dir), dir / "bad.ply",
                     "4 bytes follow the end of the last element's data", "binary PLY");
  append(dir / "model.spz", dir / "bad.spz", "junk");
  expect_clean_error(test::run_command(render(dir / "bad.spz"), dir), dir / "bad.spz",
                     "4 bytes follow the end of the gzip stream", ".spz");
  // A .splat has no header: its length must be whole records.
  append(dir / "model.splat", dir / "bad.splat", "junk");
  expect_clean_error(test::run_command(render(dir / "bad.splat"), dir), dir / "bad.splat", "bytes", ".splat");
  EXPECT_FALSE(fs::exists(dir / "render")) << "a refused model created the output folder";
  EXPECT_FALSE(fs::exists(dir / "resumed")) << "a refused checkpoint created the output folder";

  // An ASCII PLY: blank lines at the end are fine, a further row is not.
  const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                            "property float z\nproperty float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\n"
                            "property float opacity\nproperty float scale_0\nproperty float scale_1\n"
                            "property float scale_2\nproperty float rot_0\nproperty float rot_1\n"
                            "property float rot_2\nproperty float rot_3\nend_header\n"
                            "0 0 0 0.5 0.5 0.5 2 -3 -3 -3 1 0 0 0\n";
  test::write_text(dir / "ascii.ply", ascii + "\n\n");
  const auto good = test::run_command(render(dir / "ascii.ply"), dir);
  EXPECT_EQ(good.exit_code, 0) << good.err;
  test::write_text(dir / "bad_ascii.ply", ascii + "0 0 0 0.5 0.5 0.5 2 -3 -3 -3 1 0 0 0\n");
  expect_clean_error(test::run_command(render(dir / "bad_ascii.ply"), dir), dir / "bad_ascii.ply",
                     "text follows the last element's rows", "ASCII PLY");
}

}  // namespace
}  // namespace splat
