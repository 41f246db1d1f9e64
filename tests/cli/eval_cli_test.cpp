// splat-eval end to end on a tiny dataset rendered from the built-in demo model, with a
// budget of a second or two per method and small trainer settings: both methods train, are
// scored over time and rendered, and every output the contract names is there and consistent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/orbit_cameras.hpp"
#include "splat/data/rendered_dataset.hpp"
#include "splat/gaussians/demo_model.hpp"
#include "test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

constexpr int kSize = 32;

// 8 training and 2 test views at 32x32, plus small trainer settings, in the test's own folder
// (ctest runs test cases in parallel).
fs::path tiny_dataset(const fs::path& dir) {
  const fs::path d = dir / "data";
  OrbitRig train_rig;
  train_rig.count = 8;
  train_rig.radius = 5.5f;
  train_rig.width = train_rig.height = kSize;
  OrbitRig test_rig = train_rig;
  test_rig.count = 2;
  test_rig.elevation_radians = 0.7f;
  const float white[3] = {1, 1, 1};
  write_rendered_dataset(make_demo_model(2000), orbit_cameras(train_rig), orbit_cameras(test_rig), white, d);
  test::write_text(dir / "splat.json", R"({"random_init_points": 2000, "densify_from_iter": 100,
    "densification_interval": 50, "opacity_reset_interval": 200, "densify_until_iter": 250})");
  test::write_text(dir / "nerf.json", R"({"rays_per_batch": 256, "occupancy_warmup": 100,
    "occupancy_interval": 10, "lr_init": 5e-3, "lr_final": 5e-4, "lr_decay_iterations": 400,
    "model": {"coarse": {"depth": 2, "width": 32, "skip_layer": -1, "color_width": 16},
              "fine": {"depth": 2, "width": 32, "skip_layer": -1, "color_width": 16},
              "coarse_samples": 16, "fine_samples": 16,
              "box_min": [-2.5, -2.5, -2.5], "box_max": [2.5, 2.5, 2.5]}})");
  return d;
}

std::string eval_command(const fs::path& dir, const fs::path& data, const std::string& extra) {
  return std::string(SPLAT_EVAL_EXE) + " --data " + data.string() + " --out " + (dir / "out").string() +
         " --splat-config " + (dir / "splat.json").string() + " --nerf-config " +
         (dir / "nerf.json").string() + " " + extra;
}

TEST(EvalCli, TrainsBothMethodsAndWritesResultsModelsRendersAndGrids) {
  const fs::path dir = test::scratch_dir("eval_cli_basic");
  const fs::path data = tiny_dataset(dir);
  const auto r = test::run_command(
      eval_command(dir, data, "--max-seconds 2 --eval-every-seconds 0.5 --threads 2"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  // Progress names the method, the stage and the ETA.
  for (const char* word : {"[splat", "[nerf", "training", "evaluating", "rendering", "ETA"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word << " not in:\n" << r.out;

  const fs::path out = dir / "out";
  const auto j = nlohmann::json::parse(test::read_file(out / "results.json"));
  EXPECT_EQ(j.at("budget_seconds").get<double>(), 2.0);
  EXPECT_EQ(j.at("threads").get<int>(), 2);
  EXPECT_EQ(j.at("data").get<std::string>(), data.string());
  const auto& methods = j.at("methods");
  ASSERT_EQ(methods.size(), 2u);
  EXPECT_EQ(methods[0].at("method"), "splat");
  EXPECT_EQ(methods[1].at("method"), "nerf");
  for (const auto& m : methods) {
    const std::string name = m.at("method");
    SCOPED_TRACE(name);
    const double psnr = m.at("final").at("psnr");
    EXPECT_TRUE(std::isfinite(psnr));
    // Two seconds teach the splats the scene; the NeRF barely starts (about 200 steps), so
    // for it this only says the score is a sane number.
    EXPECT_GT(psnr, name == "splat" ? 20.0 : 5.0);
    EXPECT_TRUE(std::isfinite(m.at("final").at("ssim").get<double>()));
    // Trained for about the budget (one step may overrun it), not counting scoring time.
    EXPECT_GE(m.at("train_seconds").get<double>(), 2.0);
    EXPECT_LT(m.at("train_seconds").get<double>(), 4.0);
    EXPECT_GT(m.at("render_ms_per_view_median").get<double>(), 0.0);
    const auto& history = m.at("history");
    ASSERT_GE(history.size(), 2u);
    for (std::size_t i = 0; i < history.size(); ++i) {
      for (const char* key : {"seconds", "iteration", "test_psnr", "test_ssim"})
        ASSERT_TRUE(history[i].contains(key)) << key << " missing in " << history[i].dump();
      if (i > 0) {
        EXPECT_GT(history[i].at("seconds").get<double>(), history[i - 1].at("seconds").get<double>());
        EXPECT_GT(history[i].at("iteration").get<int>(), history[i - 1].at("iteration").get<int>());
      }
    }
    const fs::path model = out / m.at("model_file").get<std::string>();
    ASSERT_TRUE(fs::exists(model)) << model;
    EXPECT_EQ(fs::file_size(model), m.at("model_bytes").get<std::uintmax_t>());
    EXPECT_GT(m.at("num_params").get<std::size_t>(), 0u);
    for (const char* view : {"view_000", "view_001"})
      EXPECT_TRUE(fs::exists(out / name / "test" / (std::string(view) + ".png"))) << view;
  }
  EXPECT_EQ(methods[0].at("model_file"), "splat/model.ply");
  EXPECT_EQ(methods[1].at("model_file"), "nerf/model.nerf");
  EXPECT_GT(methods[0].at("num_gaussians").get<std::size_t>(), 0u);
  EXPECT_FALSE(methods[1].contains("num_gaussians"));
  for (const char* view : {"view_000", "view_001"}) {
    const Image grid = read_image(out / "grids" / (std::string(view) + ".png"));
    EXPECT_EQ(grid.width, 5 * kSize) << view;
    EXPECT_EQ(grid.height, kSize) << view;
  }
  // Charts through gnuplot (a dependency: scripts/install-deps.sh), PNG and SVG.
  const std::vector<std::string> charts = j.at("charts");
  for (const char* chart : {"charts/psnr_vs_time.png", "charts/psnr_vs_time.svg", "charts/ssim_vs_time.png",
                            "charts/ssim_vs_time.svg"}) {
    EXPECT_NE(std::find(charts.begin(), charts.end(), chart), charts.end()) << chart;
    EXPECT_GT(fs::file_size(out / chart), 1000u) << chart;
  }
  EXPECT_EQ(read_image(out / "charts" / "psnr_vs_time.png").width, 900);
}

TEST(EvalCli, MissingDataFolderIsNamedAndLeavesNoOutput) {
  const fs::path dir = test::scratch_dir("eval_cli_missing");
  const fs::path missing = dir / "no_such_dataset";
  const auto r = test::run_command(std::string(SPLAT_EVAL_EXE) + " --data " + missing.string() +
                                       " --out " + (dir / "out").string() + " --max-seconds 1",
                                   dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("no_such_dataset"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out")) << "output folder created for a failed run";
}

TEST(EvalCli, RejectsBadOptions) {
  const fs::path dir = test::scratch_dir("eval_cli_options");
  for (const char* bad : {"--max-seconds 0", "--eval-every-seconds -1", "--threads 0", "--bg green"}) {
    const auto r = test::run_command(std::string(SPLAT_EVAL_EXE) + " --data " + dir.string() + " --out " +
                                         (dir / "out").string() + " " + bad,
                                     dir);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir / "out")) << bad;
  }
}

}  // namespace
}  // namespace splat
