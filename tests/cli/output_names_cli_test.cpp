// Outputs named after inputs never collide: two views that would share a name are either made
// unique (the same stem in two folders: the folder joins the name) or refused (the same image
// listed twice), so no command writes one file twice and silently keeps the second.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "splat/data/view_names.hpp"
#include "splat/core/error.hpp"
#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

TEST(ViewNames, StemsUnlessTheyCollideThenTheFolderJoinsTheNameAndTheSameImageTwiceIsRefused) {
  EXPECT_EQ(view_names({"train/r_0.png", "train/r_1.png"}, "t.json"),
            (std::vector<std::string>{"r_0", "r_1"}));
  EXPECT_EQ(view_names({"cam1/0001.jpg", "cam2/0001.jpg", "cam1/0002.jpg"}, "images.txt"),
            (std::vector<std::string>{"cam1_0001", "cam2_0001", "0002"}));
  EXPECT_EQ(view_names({"./a/x.png", "a/../b/x.png"}, "t.json"), (std::vector<std::string>{"a_x", "b_x"}));
  try {
    view_names({"train/r_1", "train/r_2", "./train/r_1"}, "t.json");
    ADD_FAILURE() << "the same image twice was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.json: views 0 and 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'train_r_1'"), std::string::npos) << e.what();
  }
}

TEST(OutputNames, SplatRenderRefusesTwoFramesOfOneNameAndKeepsFramesOfTwoFoldersApart) {
  const fs::path dir = test::scratch_dir("output_names");
  ASSERT_EQ(test::run_command(std::string(SPLAT_DEMO_EXE) + " --out " + (dir / "demo").string() +
                                  " --gaussians 500 --views 2 --size 32", dir)
                .exit_code, 0);
  nlohmann::json cameras = nlohmann::json::parse(test::read_file(dir / "demo" / "cameras.json"));
  const auto render = [&](const std::string& first, const std::string& second, const fs::path& out) {
    cameras["frames"][0]["file_path"] = first;
    cameras["frames"][1]["file_path"] = second;
    test::write_text(dir / "cameras.json", cameras.dump());
    return test::run_command(std::string(SPLAT_RENDER_EXE) + " --model " + (dir / "demo" / "model.ply").string() +
                                 " --cameras " + (dir / "cameras.json").string() + " --out " + out.string(), dir);
  };
  const auto refused = render("./train/r_1", "train/r_1", dir / "refused");
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_EQ(refused.err.rfind("error: " + (dir / "cameras.json").string() + ": views 0 and 1", 0), 0u) << refused.err;
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
  EXPECT_FALSE(fs::exists(dir / "refused"));

  const auto apart = render("left/r_1", "right/r_1", dir / "apart");
  ASSERT_EQ(apart.exit_code, 0) << apart.err;
  EXPECT_TRUE(fs::exists(dir / "apart" / "left_r_1.png"));
  EXPECT_TRUE(fs::exists(dir / "apart" / "right_r_1.png"));
}

}  // namespace
}  // namespace splat
