// splat-eval end to end on a tiny dataset rendered from the built-in demo model, with a
// budget of a second or two per method and small trainer settings: the methods train, are
// scored over time and rendered, and every output the contract names is there and consistent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "tests/data/dataset_test_folders.hpp"
#include "tests/cli_support.hpp"
#include "splat/data/image_io.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

constexpr int kSize = 32;

// 8 training and 2 test views at 32x32, plus small trainer settings, in the test's own folder
// (ctest runs test cases in parallel).
fs::path tiny_dataset(const fs::path& dir) {
  const fs::path d = dir / "data";
  test::write_demo_dataset(d, 8, 2, kSize, 2000);
  // The schedule is not fitted to these short runs: decayed within 500 iterations, the
  // position step leaves the random start where it is (train_cli_test.cpp alike).
  test::write_text(dir / "splat.json", R"({"iterations": 500, "random_init_points": 2000, "densify_from_iter": 100,
    "densification_interval": 50, "opacity_reset_interval": 200, "densify_until_iter": 250,
    "compact_warmup_until": 60, "compact_grow_from": 100, "compact_grow_interval": 50,
    "compact_grow_until": 250, "compact_prune_window": 50, "schedule_follows_budget": false})");
  test::write_text(dir / "nerf.json", R"({"iterations": 200, "rays_per_batch": 256, "occupancy_warmup": 100,
    "occupancy_interval": 10, "lr_init": 5e-3, "lr_final": 5e-4, "lr_decay_iterations": 400,
    "model": {"coarse": {"depth": 2, "width": 32, "skip_layer": -1, "color_width": 16},
              "fine": {"depth": 2, "width": 32, "skip_layer": -1, "color_width": 16},
              "coarse_samples": 16, "fine_samples": 16, "render_sample_multiplier": 1,
              "box_min": [-2.5, -2.5, -2.5], "box_max": [2.5, 2.5, 2.5]}})");
  test::write_text(dir / "ngp.json", R"({"method": "ngp", "iterations": 200, "rays_per_batch": 256,
    "model": {"coarse": {"hash": {"levels": 4, "table_log2": 10, "max_resolution": 32}},
              "fine": {"hash": {"levels": 8, "table_log2": 12, "max_resolution": 64}},
              "coarse_samples": 16, "fine_samples": 8, "render_sample_multiplier": 1,
              "box_min": [-2.5, -2.5, -2.5], "box_max": [2.5, 2.5, 2.5]}})");
  // (Scores at the training's sample count: the tests below need the history of scores
  // that the 10 % limit on scoring time lets this short run afford.)
  return d;
}

std::string eval_command(const fs::path& dir, const fs::path& data, const std::string& extra) {
  return std::string(SPLAT_EVAL_EXE) + " --data " + data.string() + " --out " + (dir / "out").string() +
         " --splat-config " + (dir / "splat.json").string() + " --nerf-config " +
         (dir / "nerf.json").string() + " --ngp-config " + (dir / "ngp.json").string() + " " + extra;
}

// report.html exists, shows each of `expected`, and every file it names is there.
void expect_report_files_exist(const fs::path& out, const std::vector<std::string>& expected) {
  const std::string html = test::read_file(out / "report.html");
  for (const std::string& file : expected) EXPECT_NE(html.find("\"" + file + "\""), std::string::npos) << file;
  for (const char* attribute : {"src=\"", "href=\""}) {
    for (std::size_t at = html.find(attribute); at != std::string::npos; at = html.find(attribute, at + 1)) {
      const std::size_t start = at + std::string(attribute).size();
      const std::string file = html.substr(start, html.find('"', start) - start);
      EXPECT_TRUE(fs::exists(out / file)) << "report.html names a missing file: " << file;
    }
  }
}

TEST(EvalCli, TrainsBothMethodsAndWritesResultsModelsRendersAndGrids) {
  const fs::path dir = test::scratch_dir("eval_cli_basic");
  const fs::path data = tiny_dataset(dir);
  const auto r = test::run_command(
      eval_command(dir, data, "--methods splat,nerf --max-seconds 60 --eval-every-seconds 0.05 --threads 2"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  // Progress names the method, the stage and the ETA.
  for (const char* word : {"[splat", "[nerf", "training", "scoring", "ETA"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word << " not in:\n" << r.out;

  const fs::path out = dir / "out";
  const auto j = nlohmann::json::parse(test::read_file(out / "results.json"));
  EXPECT_EQ(j.at("budget_seconds").get<double>(), 60.0);
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
    // The iteration limits (500 splat, 200 NeRF steps, from the configs) end both runs long
    // before the budget, so the models do not depend on the machine's load: 500 steps teach
    // the splats the scene; the NeRF barely starts, so for it this says the score is sane.
    EXPECT_EQ(m.at("stopped_by"), "iterations");
    EXPECT_EQ(m.at("iterations").get<int>(), name == "splat" ? 500 : 200);
    EXPECT_GT(psnr, name == "splat" ? 20.0 : 5.0);
    EXPECT_TRUE(std::isfinite(m.at("final").at("ssim").get<double>()));
    EXPECT_LT(m.at("train_seconds").get<double>(), 60.0);
    EXPECT_GT(m.at("render_ms_per_view_median").get<double>(), 0.0);
    // What scoring cost: its limit during training, its share, the final score's seconds.
    EXPECT_EQ(m.at("scoring").at("share_limit").get<double>(), 0.1);
    EXPECT_GE(m.at("scoring").at("share").get<double>(), 0.0);
    EXPECT_GT(m.at("scoring").at("final_score_seconds").get<double>(), 0.0);
    EXPECT_GE(m.at("scoring").at("skipped_scores").get<int>(), 0);
    const auto& history = m.at("history");
    // Scores fall due every 0.05 s of a run that trains for longer; each is taken or, when it
    // would push scoring past its share, skipped. Which of the two depends on the machine's
    // load (under CI's the NeRF's were all skipped), but at least one fell due, and the final
    // score is always there.
    ASSERT_GE(history.size(), 1u);
    EXPECT_GE(history.size() - 1 + m.at("scoring").at("skipped_scores").get<std::size_t>(), 1u);
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
  for (const auto& m : methods)
    for (const auto& h : m.at("history")) {
      ASSERT_TRUE(h.contains("model_bytes")) << h.dump();
      EXPECT_GT(h.at("model_bytes").get<std::size_t>(), 0u);
    }
  // Charts through gnuplot (a dependency: scripts/install-deps.sh), PNG and SVG.
  for (const char* chart : {"psnr_vs_time", "ssim_vs_time", "psnr_vs_model_bytes", "render_ms_vs_psnr"})
    for (const char* ext : {".png", ".svg"})
      EXPECT_GT(fs::file_size(out / "charts" / (std::string(chart) + ext)), 1000u) << chart << ext;
  EXPECT_EQ(read_image(out / "charts" / "psnr_vs_time.png").width, 900);
  expect_report_files_exist(out, {"charts/psnr_vs_time.png", "charts/render_ms_vs_psnr.png", "grids/view_001.png"});
}

TEST(EvalCli, MethodsDefaultToBothDensityStrategiesAndTheNerfEachWithItsFolderEntryAndPanels) {
  const fs::path dir = test::scratch_dir("eval_cli_methods");
  const fs::path data = tiny_dataset(dir);
  // A "strategy" in --splat-config is dropped (with a warning): the method names the strategy,
  // and the file's other settings (the 500 iterations) apply to both splat methods.
  auto settings = nlohmann::json::parse(test::read_file(dir / "splat.json"));
  settings["strategy"] = "official";
  test::write_text(dir / "splat.json", settings.dump());
  const auto r = test::run_command(eval_command(dir, data, "--max-seconds 60 --eval-every-seconds 0.5"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.err.find("warning: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\"strategy\" ignored"), std::string::npos) << r.err;
  for (const char* word : {"[splat 1/4]", "[splat-official 2/4]", "[nerf 3/4]", "[ngp 4/4]"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word << " not in:\n" << r.out;

  const fs::path out = dir / "out";
  const auto j = nlohmann::json::parse(test::read_file(out / "results.json"));
  const auto& methods = j.at("methods");
  ASSERT_EQ(methods.size(), 4u);
  const std::string names[] = {"splat", "splat-official", "nerf", "ngp"};
  const std::string strategies[] = {"compact", "official", "", ""};
  const std::string models[] = {"splat/model.ply", "splat-official/model.ply", "nerf/model.nerf", "ngp/model.ngp"};
  for (int i = 0; i < 4; ++i) {
    const auto& m = methods[i];
    SCOPED_TRACE(names[i]);
    EXPECT_EQ(m.at("method"), names[i]);
    EXPECT_EQ(m.at("model_file"), models[i]);
    EXPECT_TRUE(fs::exists(out / models[i]));
    EXPECT_TRUE(fs::exists(out / names[i] / "test" / "view_000.png"));
    EXPECT_EQ(m.at("stopped_by"), "iterations");
    if (strategies[i].empty()) {
      EXPECT_FALSE(m.contains("strategy"));
      EXPECT_FALSE(m.contains("num_gaussians"));
      continue;
    }
    EXPECT_EQ(m.at("strategy"), strategies[i]);
    EXPECT_EQ(m.at("config").at("strategy"), strategies[i]);
    EXPECT_EQ(m.at("iterations").get<int>(), 500);
    EXPECT_GT(m.at("final").at("psnr").get<double>(), 20.0);
    for (const auto& h : m.at("history")) EXPECT_GT(h.at("num_gaussians").get<std::size_t>(), 0u) << h.dump();
  }
  const std::vector<std::string> panels = {"ground truth", "splat",       "splat-official",       "nerf",
                                           "ngp",          "splat error", "splat-official error", "nerf error",
                                           "ngp error"};
  EXPECT_EQ(j.at("grid").at("panels").get<std::vector<std::string>>(), panels);
  const Image grid = read_image(out / "grids" / "view_001.png");
  EXPECT_EQ(grid.width, 9 * kSize);
  EXPECT_EQ(grid.height, kSize);
  for (const char* chart : {"psnr_vs_time", "psnr_vs_model_bytes", "psnr_vs_gaussians"})
    EXPECT_GT(fs::file_size(out / "charts" / (std::string(chart) + ".png")), 1000u) << chart;
  expect_report_files_exist(out, {"charts/psnr_vs_gaussians.png", "grids/view_000.png"});
  const std::string html = test::read_file(out / "report.html");
  for (const char* label : {"splat (compact)", "splat (official)", "NeRF", "NGP", "splat-official error"})
    EXPECT_NE(html.find(label), std::string::npos) << label;
  // The verdicts name the method with the best final score.
  const std::map<std::string, std::string> labels = {
      {"splat", "splat (compact)"}, {"splat-official", "splat (official)"}, {"nerf", "NeRF"}, {"ngp", "NGP"}};
  const auto top = std::max_element(methods.begin(), methods.end(), [](const auto& a, const auto& b) {
    return a.at("final").at("psnr").template get<double>() < b.at("final").at("psnr").template get<double>();
  });
  EXPECT_NE(html.find("best test PSNR: <b>" + labels.at(top->at("method").get<std::string>()) + "</b>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("the best score every method reached during training"), std::string::npos);

  // --report on a results.json from before --methods: splat and nerf, no strategies.
  const fs::path old = dir / "old";
  fs::create_directories(old);
  auto before = j;
  before["methods"] = {methods[0], methods[2]};
  before["methods"][0].erase("strategy");
  before["grid"]["panels"] = {"ground truth", "splat", "nerf", "splat error", "nerf error"};
  before.erase("grids");  // the images stay in the other folder
  test::write_text(old / "results.json", before.dump());
  const auto again = test::run_command(std::string(SPLAT_EVAL_EXE) + " --report --quiet --out " + old.string(), dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  expect_report_files_exist(old, {"charts/psnr_vs_time.png", "charts/psnr_vs_gaussians.png"});
}

// A capture as COLMAP leaves it (sparse/0 and images/, one camera for all photographs, test
// views every 8th in name order) runs the comparison as a Blender folder does.
TEST(EvalCli, ComparesTheMethodsOnACOLMAPCapture) {
  const fs::path dir = test::scratch_dir("eval_cli_colmap");
  tiny_dataset(dir);  // for the small trainer settings
  test::TestModel model;
  model.cameras = {{1, ColmapCameraModel::kPinhole, 24, 18, {22.0, 22.0, 12.0, 9.0}}};
  for (int i = 0; i < 10; ++i) {
    ColmapImage image;
    image.id = std::uint32_t(1 + i);
    // Cameras on an arc 4 units from the origin, looking at it (a turn about y).
    const double angle = 0.08 * (i - 5);
    image.quaternion = {std::cos(angle / 2), 0.0, std::sin(angle / 2), 0.0};
    image.translation = {0.0, 0.0, 4.0};
    image.camera_id = 1;
    image.name = "img_" + std::to_string(10 + i) + ".png";
    model.images.push_back(image);
  }
  for (int i = 0; i < 30; ++i)
    model.points.push_back({{0.05 * (i % 5) - 0.1, 0.05 * (i / 5) - 0.15, 0.02 * (i % 3)}, {200, 90, std::uint8_t(8 * i)}});
  test::write_colmap_folder(dir / "capture", model, test::ModelForm::kText);

  const auto r = test::run_command(
      eval_command(dir, dir / "capture", "--methods splat,nerf --max-seconds 1 --eval-every-seconds 0.5"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(test::read_file(dir / "out" / "results.json"));
  EXPECT_EQ(j.at("test_views").get<int>(), 2);  // img_10 and img_18
  ASSERT_EQ(j.at("methods").size(), 2u);
  for (const auto& m : j.at("methods")) EXPECT_TRUE(std::isfinite(m.at("final").at("psnr").get<double>())) << m.dump();
  EXPECT_TRUE(fs::exists(dir / "out" / "grids" / "img_10.png"));
  expect_report_files_exist(dir / "out", {"grids/img_10.png"});

  // Photographs with structure from motion are a real capture: the stability baseline is its
  // row, and each run says whether it held its best.
  const auto s = test::run_command(
      eval_command(dir, dir / "capture",
                   "--stability --stability-conditions baseline --max-seconds 1 --eval-every-seconds 0.25 --quiet"),
      dir);
  ASSERT_EQ(s.exit_code, 0) << s.err << s.out;
  const auto stability = nlohmann::json::parse(test::read_file(dir / "out" / "stability.json"));
  EXPECT_TRUE(stability.at("real_capture").get<bool>());
  EXPECT_TRUE(stability.at("rules").contains("holds_best"));
  ASSERT_EQ(stability.at("conditions").size(), 1u);
  const auto& baseline = stability.at("conditions")[0];
  EXPECT_EQ(baseline.at("name"), "real capture, all 8 views");
  ASSERT_EQ(baseline.at("runs").size(), 2u);
  for (const auto& run : baseline.at("runs"))
    EXPECT_EQ(run.at("holds_best").get<bool>(), run.at("drop_from_best").get<double>() <= 0.3) << run.dump();
  const std::string report = test::read_file(dir / "out" / "report.html");
  EXPECT_NE(report.find("Real capture: does training hold its best?"), std::string::npos);
  expect_report_files_exist(dir / "out", {"charts/stability_real_capture.png"});
}

TEST(EvalCli, StabilityAndSweepRunTheMethodsGiven) {
  const fs::path dir = test::scratch_dir("eval_cli_methods_modes");
  const fs::path data = tiny_dataset(dir);
  auto r = test::run_command(
      eval_command(dir, data, "--stability --stability-views 4 --methods splat-official --max-seconds 0.3"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const fs::path out = dir / "out";
  const auto stability = nlohmann::json::parse(test::read_file(out / "stability.json"));
  for (const auto& c : stability.at("conditions")) {
    if (c.contains("skipped")) continue;
    ASSERT_EQ(c.at("runs").size(), 1u) << c.dump();
    EXPECT_EQ(c.at("runs")[0].at("method"), "splat-official");
    EXPECT_EQ(c.at("runs")[0].at("strategy"), "official");
  }
  EXPECT_NE(test::read_file(out / "report.html").find("splat (official) verdict"), std::string::npos);

  r = test::run_command(eval_command(dir, data, "--sweep-gaussians 1000 --methods splat-official --max-seconds 0.3"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto sweep = nlohmann::json::parse(test::read_file(out / "sweep.json"));
  EXPECT_EQ(sweep.at("method"), "splat-official");
  EXPECT_EQ(sweep.at("strategy"), "official");
  EXPECT_EQ(sweep.at("runs")[0].at("strategy"), "official");
  // Without --methods the sweep trains splat, the compact strategy.
  r = test::run_command(eval_command(dir, data, "--sweep-gaussians 1000 --max-seconds 0.3 --quiet"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(test::read_file(out / "sweep.json")).at("strategy"), "compact");
}

TEST(EvalCli, StabilityRunsEveryConditionAndGivesEachRunAVerdict) {
  const fs::path dir = test::scratch_dir("eval_cli_stability");
  const fs::path data = tiny_dataset(dir);
  const auto r = test::run_command(eval_command(dir, data, "--stability --stability-views 4,8 --max-seconds 0.5"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const fs::path out = dir / "out";
  const auto j = nlohmann::json::parse(test::read_file(out / "stability.json"));
  EXPECT_GT(j.at("background_only_psnr").get<double>(), 0.0);
  EXPECT_GE(j.at("failure_psnr").get<double>(), 20.0);  // the absolute floor, stated
  EXPECT_GE(j.at("failure_psnr").get<double>(), j.at("background_only_psnr").get<double>() + 3.0);
  for (const char* rule : {"ok", "degraded", "failed", "diverged", "collapsed"}) EXPECT_TRUE(j.at("rules").contains(rule)) << rule;
  EXPECT_FALSE(j.at("real_capture").get<bool>());  // rendered views, no structure from motion
  std::vector<std::string> names;
  for (const auto& c : j.at("conditions")) {
    const std::string id = c.at("id");
    names.push_back(id);
    SCOPED_TRACE(id);
    // 8 views is the whole dataset: skipped, as is random initialisation (no point cloud).
    if (id == "views_8" || id == "random_init") {
      EXPECT_TRUE(c.contains("skipped"));
      continue;
    }
    // Pose refinement is the splat methods' alone: the NeRF does not run in those rows.
    const bool refined = c.at("kind").get<std::string>().find("+ refinement") != std::string::npos;
    EXPECT_EQ(refined, id.size() > 7 && id.substr(id.size() - 7) == "_refine");
    ASSERT_EQ(c.at("runs").size(), refined ? 1u : 2u);
    if (refined) {
      EXPECT_EQ(c.at("runs")[0].at("method"), "splat");
      EXPECT_NE(c.at("runs")[0].at("pose_refinement").at("test_protocol").get<std::string>().find("aligned"),
                std::string::npos);
    } else {
      EXPECT_FALSE(c.at("runs")[0].contains("pose_refinement"));
    }
    EXPECT_EQ(c.at("train_views").get<int>(), id == "views_4" ? 4 : 8);
    for (const auto& run : c.at("runs")) {
      const std::string verdict = run.at("verdict");
      EXPECT_TRUE(verdict == "ok" || verdict == "degraded" || verdict == "failed" || verdict == "collapsed" ||
                  verdict == "diverged")
          << verdict;
      ASSERT_TRUE(run.contains("final")) << run.dump();
      // Stopped by the 0.5 s budget (one step may overrun it), scoring not counted.
      if (run.at("stopped_by") == "time") {
        EXPECT_GE(run.at("train_seconds").get<double>(), 0.5);
        EXPECT_LT(run.at("train_seconds").get<double>(), 2.5);
      }
      EXPECT_TRUE(std::isfinite(run.at("final").at("psnr").get<double>()));
      EXPECT_TRUE(fs::exists(out / run.at("model_file").get<std::string>()));
      // The best test point of the run, and how far the end fell below it.
      double best = run.at("final").at("psnr");
      for (const auto& h : run.at("history")) best = std::max(best, h.at("test_psnr").get<double>());
      EXPECT_EQ(run.at("best").at("psnr").get<double>(), best);
      EXPECT_NEAR(run.at("drop_from_best").get<double>(), best - run.at("final").at("psnr").get<double>(), 1e-12);
    }
  }
  const std::vector<std::string> expected = {"baseline",
                                             "baseline_refine",
                                             "views_4",
                                             "views_8",
                                             "pose_noise_0.25deg_0.25pct",
                                             "pose_noise_0.25deg_0.25pct_refine",
                                             "pose_noise_1deg_1pct",
                                             "pose_noise_1deg_1pct_refine",
                                             "pose_noise_3deg_3pct",
                                             "pose_noise_3deg_3pct_refine",
                                             "random_init"};
  EXPECT_EQ(names, expected);
  EXPECT_GT(fs::file_size(out / "charts" / "stability_psnr.png"), 1000u);
  EXPECT_GT(fs::file_size(out / "charts" / "stability_curves.png"), 1000u);
  expect_report_files_exist(out, {"charts/stability_psnr.png", "charts/stability_curves.png"});
  EXPECT_FALSE(fs::exists(out / "charts" / "stability_real_capture.png"));
  const std::string report = test::read_file(out / "report.html");
  EXPECT_NE(report.find("below its best (dB)"), std::string::npos);
  EXPECT_NE(report.find("poses 1° / 1% + refinement"), std::string::npos);
  EXPECT_NE(report.find("aligned to its photograph"), std::string::npos);
  EXPECT_NE(report.find("after refinement"), std::string::npos);
}

TEST(EvalCli, StabilityRunsTheConditionKindsAndNoiseLevelsGiven) {
  const fs::path dir = test::scratch_dir("eval_cli_stability_kinds");
  const fs::path data = tiny_dataset(dir);
  const auto r = test::run_command(
      eval_command(dir, data, "--stability --stability-conditions baseline,refinement --pose-noise 2 --max-seconds 0.3"),
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(test::read_file(dir / "out" / "stability.json"));
  std::vector<std::string> names;
  for (const auto& c : j.at("conditions")) names.push_back(c.at("id"));
  const std::vector<std::string> expected = {"baseline", "baseline_refine", "pose_noise_2deg_2pct_refine"};
  EXPECT_EQ(names, expected);
  // With the NeRF alone, the refinement rows say why they did not run.
  const auto nerf = test::run_command(
      eval_command(dir, data, "--stability --methods nerf --stability-conditions refinement --pose-noise 2 --max-seconds 0.3"),
      dir);
  ASSERT_EQ(nerf.exit_code, 0) << nerf.err << nerf.out;
  // Parsed into a local: a range-for over .at() of the temporary would read it after it died.
  const nlohmann::json nerf_only = nlohmann::json::parse(test::read_file(dir / "out" / "stability.json"));
  for (const auto& c : nerf_only.at("conditions"))
    EXPECT_NE(c.value("skipped", "").find("splat methods"), std::string::npos) << c.dump();
  // The refined runs are judged against the plain splat baseline.
  for (const auto& c : j.at("conditions"))
    for (const auto& run : c.at("runs")) EXPECT_TRUE(run.contains("verdict")) << run.dump();
  // They measure how far their training cameras are from the true poses, before and after.
  const auto& clean = j.at("conditions")[1].at("runs")[0].at("pose_refinement").at("pose_error");
  const auto& noisy = j.at("conditions")[2].at("runs")[0].at("pose_refinement").at("pose_error");
  EXPECT_LT(clean.at("before").at("mean_rotation_deg").get<double>(), 1e-3) << clean.dump();
  EXPECT_GT(noisy.at("before").at("mean_rotation_deg").get<double>(), 1.0) << noisy.dump();
  EXPECT_LT(noisy.at("before").at("mean_rotation_deg").get<double>(), 2.5) << noisy.dump();
  EXPECT_TRUE(noisy.at("after").contains("mean_translation_percent_of_extent")) << noisy.dump();
}

TEST(EvalCli, GaussianSweepMarksTheSmallestModelWithinHalfADecibelOfTheBest) {
  const fs::path dir = test::scratch_dir("eval_cli_sweep");
  const fs::path data = tiny_dataset(dir);
  const auto r = test::run_command(eval_command(dir, data, "--sweep-gaussians 300,3000 --max-seconds 1"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const fs::path out = dir / "out";
  const auto j = nlohmann::json::parse(test::read_file(out / "sweep.json"));
  const auto& runs = j.at("runs");
  ASSERT_EQ(runs.size(), 2u);
  double best = 0;
  for (const auto& run : runs) {
    EXPECT_LE(run.at("num_gaussians").get<std::size_t>(), run.at("max_gaussians").get<std::size_t>());
    EXPECT_EQ(fs::file_size(out / run.at("model_file").get<std::string>()), run.at("model_bytes").get<std::size_t>());
    best = std::max(best, run.at("final").at("psnr").get<double>());
  }
  EXPECT_DOUBLE_EQ(j.at("best_psnr").get<double>(), best);
  // The mark: within 0.5 dB of the best, and no other run within it is smaller.
  const std::size_t mark = j.at("smallest_within");
  EXPECT_GE(runs[mark].at("final").at("psnr").get<double>(), best - 0.5);
  for (const auto& run : runs) {
    if (run.at("final").at("psnr").get<double>() >= best - 0.5) {
      EXPECT_GE(run.at("model_bytes").get<std::size_t>(), runs[mark].at("model_bytes").get<std::size_t>());
    }
  }
  EXPECT_GT(fs::file_size(out / "charts" / "sweep_psnr_vs_gaussians.png"), 1000u);
  expect_report_files_exist(out, {"charts/sweep_psnr_vs_gaussians.png"});

  // --report redraws the page and charts from the result files alone.
  fs::remove(out / "report.html");
  fs::remove(out / "charts" / "sweep_psnr_vs_gaussians.png");
  const auto again = test::run_command(std::string(SPLAT_EVAL_EXE) + " --report --quiet --out " + out.string(), dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  expect_report_files_exist(out, {"charts/sweep_psnr_vs_gaussians.png"});
}

// --fly-through: each method flies the same orbit (framed from the training cameras), and the
// report shows the videos side by side.
TEST(EvalCli, FlyThroughsOfEveryMethodSideBySideInTheReport) {
  SPLAT_SKIP_WITHOUT_FFMPEG();
  const fs::path dir = test::scratch_dir("eval_cli_fly_through");
  const fs::path data = tiny_dataset(dir);
  const auto r = test::run_command(eval_command(dir, data, "--methods splat,nerf --max-seconds 4 --fly-through 6"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const fs::path out = dir / "out";
  const auto j = nlohmann::json::parse(test::read_file(out / "results.json"));
  for (const auto& m : j.at("methods")) {
    const std::string video = m.at("fly_through");
    EXPECT_EQ(video, m.at("method").get<std::string>() + "/orbit.mp4");
    EXPECT_EQ(test::video_frame_count(out / video), 6) << video;
  }
  expect_report_files_exist(out, {"splat/orbit.mp4", "nerf/orbit.mp4"});
  EXPECT_NE(test::read_file(out / "report.html").find("<h3>Fly-throughs</h3>"), std::string::npos);

  for (const char* bad : {"--fly-through 0", "--fly-through 6 --stability", "--fly-through 6 --sweep-gaussians 100"}) {
    const auto b = test::run_command(eval_command(dir, data, std::string("--out ") + (dir / "bad").string() + " " + bad), dir);
    EXPECT_EQ(b.exit_code, 2) << bad;
    EXPECT_NE(b.err.find("--fly-through"), std::string::npos) << bad << ": " << b.err;
    EXPECT_FALSE(fs::exists(dir / "bad")) << bad;
  }
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

// --report on result files that are not what splat-eval writes: one line naming the file and
// the problem (not the JSON library's raw message), and no chart left half-written.
TEST(EvalCli, ReportOnDamagedResultFilesNamesTheFileAndLeavesNoTemporaryCharts) {
  const fs::path dir = test::scratch_dir("eval_cli_damaged_report");
  const std::string method = R"("method": "splat", "final": {"psnr": 20, "ssim": 0.5, "views": 1},
      "num_params": 10, "model_bytes": 100, "render_ms_per_view_median": 1)";
  struct Case {
    const char* name;
    std::string results;
    const char* expected;
  };
  const Case cases[] = {
      {"empty_history", R"({"methods": [{)" + method + R"(, "history": []}]})", ""},
      // Nothing scored at all: not what a run writes, named before any chart is drawn (not
      // "gnuplot not found", as it was).
      {"no_scores", R"({"methods": [{"method": "splat", "history": []}, {"method": "nerf", "history": []}]})",
       "results.json: not a splat-eval result file as expected"},
      {"history_not_an_array", R"({"methods": [{)" + method + R"(, "history": 7}]})", "results.json: "},
      {"history_entry_without_seconds", R"({"methods": [{)" + method + R"(, "history": [{"test_psnr": 20}]}]})",
       "results.json: "},
      {"no_methods", R"({"data": "x"})", "results.json: "},
      {"not_json", "{\"methods\": [", "results.json: malformed JSON"},
      // Found by the fuzzer (fuzz/regressions/result_json/): a key missing from "grid" was read
      // through the const operator[], which is undefined behaviour for a missing key.
      {"grid_without_error_map",
       test::read_file(fs::path(SPLAT_SOURCE_DIR) / "fuzz/regressions/result_json/grid_without_error_map.json"),
       "results.json: not a splat-eval result file as expected: key 'error_map' not found"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path out = dir / c.name;
    fs::create_directories(out);
    test::write_text(out / "results.json", c.results);
    const auto r = test::run_command(std::string(SPLAT_EVAL_EXE) + " --report --quiet --out " + out.string(), dir);
    // An empty history may be drawn without its curve, or refused (this file lacks the other
    // figures a report shows); either way cleanly.
    if (std::string(c.expected).empty() && r.exit_code == 0) {
      EXPECT_TRUE(fs::exists(out / "report.html"));
    } else {
      EXPECT_EQ(r.exit_code, 2);
      EXPECT_EQ(r.err.rfind("error: " + (out / "results.json").string(), 0), 0u) << r.err;
      EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find("[json.exception"), std::string::npos) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    if (fs::exists(out / "charts")) {
      for (const auto& entry : fs::directory_iterator(out / "charts"))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
    }
  }
  // A folder without any result file.
  fs::create_directories(dir / "nothing");
  const auto r = test::run_command(std::string(SPLAT_EVAL_EXE) + " --report --quiet --out " + (dir / "nothing").string(), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "error: " + (dir / "nothing").string() + ": holds no results.json, sweep.json or stability.json: "
                   "nothing to report (--report redraws the charts and report of a finished splat-eval run)\n");
  EXPECT_TRUE(fs::is_empty(dir / "nothing"));
}

TEST(EvalCli, RejectsBadOptions) {
  const fs::path dir = test::scratch_dir("eval_cli_options");
  for (const char* bad : {"--max-seconds 0", "--eval-every-seconds -1", "--threads 0", "--bg green",
                          "--sweep-gaussians 10,x", "--sweep-gaussians 0", "--stability-views 8,,16",
                          "--stability --sweep-gaussians 100", "--methods splat,gauss", "--methods splat,,nerf",
                          "--methods nerf,nerf", "--methods nerf --sweep-gaussians 100",
                          "--methods splat,splat-official --sweep-gaussians 100",
                          "--stability --stability-conditions baseline,sideways", "--stability --pose-noise 0",
                          "--stability --pose-noise 1,x", "--pose-noise 1", "--stability-conditions views"}) {
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
