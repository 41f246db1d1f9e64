// splat-process end to end: photos and a video through COLMAP to a dataset splat-train
// reads (on a few photos of ../shared/data/real_cup, skipped without it), the photos that do
// not register named, and bad input (one error line, exit 2, nothing made).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "splat/data/colmap_model.hpp"
#include "splat/data/dataset.hpp"
#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

std::string process(const std::string& args) { return SPLAT_PROCESS_EXE " " + args; }

void expect_one_error_line(const test::CommandResult& r, const std::string& message, const std::string& args) {
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out << r.err;
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
}

// Photos 1..count of real_cup (neighbours on its ring), copied into `folder`.
void copy_cup_photos(const fs::path& folder, int count) {
  fs::create_directories(folder);
  for (int i = 1; i <= count; ++i) {
    const std::string name = std::to_string(i) + ".jpg";
    fs::copy_file(test::benchmark_data_dir() / "real_cup" / "images" / name, folder / name);
  }
}

TEST(ProcessCli, BadInputIsOneErrorLineAndNothingMade) {
  const fs::path dir = test::scratch_dir("process_cli_bad_input");
  fs::create_directories(dir / "empty");
  fs::create_directories(dir / "notes");
  test::write_text(dir / "notes" / "a.txt", "no photo\n");
  fs::create_directories(dir / "full");
  test::write_text(dir / "full" / "x.txt", "something\n");
  fs::create_directories(dir / "photos");
  for (const char* name : {"r_0", "r_48", "r_96"})
    fs::copy_file(test::conformance_dir() / "reference" / (std::string(name) + ".png"), dir / "photos" / (std::string(name) + ".png"));
  fs::create_directories(dir / "one");
  fs::copy_file(test::conformance_dir() / "reference" / "r_0.png", dir / "one" / "r_0.png");
  const std::string out = (dir / "out").string();
  const struct {
    std::string args, message;
  } cases[] = {
      {"--out " + out, "give --images DIR or --video FILE"},
      {"--images " + (dir / "absent").string() + " --out " + out, "absent: folder does not exist"},
      {"--images " + (dir / "empty").string() + " --out " + out, "empty: holds no images"},
      {"--images " + (dir / "notes").string() + " --out " + out, "notes: holds no images"},
      {"--images " + (dir / "photos").string() + " --video v.mp4 --out " + out, "one of them"},
      {"--video " + (dir / "absent.mp4").string() + " --out " + out, "absent.mp4: no such video file"},
      {"--images " + (dir / "photos").string() + " --out " + (dir / "full").string(), "already exists and is not empty"},
      {"--images " + (dir / "photos").string() + " --out " + out + " --frames 10", "--frames is for --video"},
      {"--images " + (dir / "photos").string() + " --out " + out + " --matcher fancy", "exhaustive or sequential"},
      {"--images " + (dir / "photos").string() + " --out " + out + " --max-size 10", "--max-size must be 0"},
      {"--images " + (dir / "one").string() + " --out " + out, "one: 1 image; structure from motion needs 3 or more"},
  };
  for (const auto& c : cases) {
    expect_one_error_line(test::run_command(process(c.args), dir), c.message, c.args);
    EXPECT_FALSE(fs::exists(out)) << c.args;
    EXPECT_FALSE(fs::exists(out + ".partial")) << c.args;
  }
  // Without COLMAP (or ffmpeg, for a video) on PATH: what to install.
  const std::string no_tools = "env PATH=" + (dir / "empty").string() + " ";
  expect_one_error_line(test::run_command(no_tools + process("--images " + (dir / "photos").string() + " --out " + out), dir),
                        "colmap not found on PATH: install it with `sudo apt-get install colmap`", "no colmap");
  test::write_text(dir / "v.mp4", "not really a video\n");
  expect_one_error_line(test::run_command(no_tools + process("--video " + (dir / "v.mp4").string() + " --out " + out), dir),
                        "ffmpeg not found on PATH: install it with `sudo apt-get install ffmpeg`", "no ffmpeg");
  EXPECT_FALSE(fs::exists(out));
}

// COLMAP's own progress comes through while a stage runs (a log gets a line when it has
// changed and 5 s have passed), and a failing stage ends in one error line quoting it, with
// nothing made. A stand-in colmap on the PATH, so this runs without the benchmark data.
TEST(ProcessCli, ColmapsProgressIsShownAndItsFailureIsOneErrorLine) {
  const fs::path dir = test::scratch_dir("process_cli_progress");
  fs::create_directories(dir / "photos");
  for (const char* name : {"r_0", "r_48", "r_96"})
    fs::copy_file(test::conformance_dir() / "reference" / (std::string(name) + ".png"), dir / "photos" / (std::string(name) + ".png"));
  fs::create_directories(dir / "bin");
  test::write_text(dir / "bin" / "colmap",
                   "#!/bin/sh\necho 'Processed file [1/3]'\nsleep 6\necho 'Processed file [2/3]'\n"
                   "echo 'the extractor gave up'\nexit 1\n");
  fs::permissions(dir / "bin" / "colmap", fs::perms::owner_all);
  const std::string out = (dir / "out").string();
  const test::CommandResult r = test::run_command(
      "env PATH=" + (dir / "bin").string() + ":/usr/bin:/bin " + process("--images " + (dir / "photos").string() + " --out " + out),
      dir);
  expect_one_error_line(r, "COLMAP's feature extraction failed (exit status 1); its last words: the extractor gave up", "fake colmap");
  EXPECT_NE(r.out.find("COLMAP 1/3: extracting features"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n  features of 1/3 images, "), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
}

// Ten neighbouring photos of the cup and two of lego (another scene, another size: a camera
// each): the cup's register, lego's are named as not placed, and the dataset loads.
TEST(ProcessCli, PhotosBecomeADatasetAndThePhotosThatDoNotRegisterAreNamed) {
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("real_cup");
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("lego400_colmap");
  const fs::path dir = test::scratch_dir("process_cli_photos");
  copy_cup_photos(dir / "photos", 10);
  for (const char* name : {"000.png", "040.png"})
    fs::copy_file(test::benchmark_data_dir() / "lego400_colmap" / "images" / name, dir / "photos" / name);
  const test::CommandResult r =
      test::run_command(process("--images " + (dir / "photos").string() + " --out " + (dir / "cup").string() +
                                " --max-size 400 --camera-per-image"),
                        dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("downscaled by 0.500: the largest, 800 x 600, to 400 x 300"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("COLMAP 3/3: mapping"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("were not placed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("000.png"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "cup" / "colmap" / "colmap.log"));
  EXPECT_FALSE(fs::exists(dir / "cup.partial"));
  const ColmapModel model = read_colmap_model(dir / "cup" / "sparse" / "0");
  EXPECT_GE(model.images.size(), 8u);
  EXPECT_LE(model.images.size(), 10u);
  for (const ColmapImage& image : model.images) EXPECT_TRUE(image.name != "000.png" && image.name != "040.png") << image.name;
  EXPECT_GE(model.cameras.size(), model.images.size());
  DatasetOptions options;
  const Dataset dataset = load_dataset(dir / "cup", options);
  EXPECT_EQ(dataset.train.size() + dataset.test.size(), model.images.size());
  EXPECT_GT(dataset.train.front().image.width, 300);  // undistorted and cut to what the lens covers
  EXPECT_LE(dataset.train.front().image.width, 400);
}

// A video made of twelve neighbouring photos: frames taken by ffmpeg, matched in sequence.
TEST(ProcessCli, AVideoBecomesADataset) {
  SPLAT_SKIP_WITHOUT_BENCHMARK_DATA("real_cup");
  const fs::path dir = test::scratch_dir("process_cli_video");
  fs::create_directories(dir / "frames");
  for (int i = 1; i <= 12; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "f_%02d.jpg", i);
    fs::copy_file(test::benchmark_data_dir() / "real_cup" / "images" / (std::to_string(i) + ".jpg"), dir / "frames" / name);
  }
  const std::string video = (dir / "cup.mp4").string();
  ASSERT_EQ(test::run_command("ffmpeg -nostdin -v error -framerate 4 -i " + (dir / "frames" / "f_%02d.jpg").string() +
                                  " -c:v libx264 -pix_fmt yuv420p " + video,
                              dir)
                .exit_code,
            0);
  const test::CommandResult r = test::run_command(
      process("--video " + video + " --frames 12 --max-size 400 --out " + (dir / "cup").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("12 frames (the sharpest of 3 candidates each)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("matching neighbouring frames"), std::string::npos) << r.out;
  const ColmapModel model = read_colmap_model(dir / "cup" / "sparse" / "0");
  EXPECT_GE(model.images.size(), 9u);
  EXPECT_EQ(model.cameras.front().width, 400);
}

}  // namespace
}  // namespace splat
