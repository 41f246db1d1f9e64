// splat-viewer --watch's model (watched_model.hpp): the newest of a training folder's
// snapshot and final model, replaced when a newer one appears, kept when a file is bad.
#include "apps/splat-viewer/watched_model.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "splat/core/error.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "tests/test_support.hpp"

namespace splat::viewer {
namespace {

namespace fs = std::filesystem;

// `seconds` after an hour ago: whole seconds apart (file systems keep whole seconds at worst),
// so the test does not depend on how fast it runs.
fs::file_time_type stamp(int seconds) {
  static const fs::file_time_type base = fs::file_time_type::clock::now() - std::chrono::hours(1);
  return base + std::chrono::seconds(seconds);
}

// `count` Gaussians written to `file`, stamped at `seconds`.
void write_model_at(const fs::path& file, int count, int seconds) {
  write_ply(test::random_model(count, 0, unsigned(count)), file);
  fs::last_write_time(file, stamp(seconds));
}

TEST(WatchedModel, FollowsTheNewestModelOfTheFolder) {
  const fs::path dir = test::scratch_dir("watched_model");
  EXPECT_FALSE(newest_model_in(dir).has_value());
  EXPECT_THROW(WatchedModel{dir}, InputError);  // nothing to show yet
  EXPECT_THROW(WatchedModel{dir / "missing"}, InputError);

  write_model_at(dir / "snapshot.ply", 10, 1);
  WatchedModel model(dir);
  EXPECT_EQ(model.gaussian_count(), 10u);
  EXPECT_EQ(model.version(), 1u);
  EXPECT_NE(model.status().find("snapshot.ply"), std::string::npos);
  EXPECT_FALSE(model.refresh());  // nothing new

  write_model_at(dir / "snapshot.ply", 20, 2);  // the trainer's next snapshot
  EXPECT_TRUE(model.refresh());
  EXPECT_EQ(model.gaussian_count(), 20u);
  EXPECT_EQ(model.version(), 2u);

  write_model_at(dir / "model.ply", 30, 3);  // the final model, newer than the snapshot
  EXPECT_TRUE(model.refresh());
  EXPECT_EQ(model.gaussian_count(), 30u);
  EXPECT_NE(model.status().find("model.ply"), std::string::npos);

  // A bad file keeps the model shown, says why, and is not read again until it changes.
  test::write_text(dir / "snapshot.ply", "ply\nnot a model\n");
  fs::last_write_time(dir / "snapshot.ply", stamp(4));
  EXPECT_FALSE(model.refresh());
  EXPECT_EQ(model.gaussian_count(), 30u);
  EXPECT_EQ(model.version(), 3u);
  EXPECT_NE(model.status().find("snapshot.ply"), std::string::npos) << model.status();
  EXPECT_FALSE(model.refresh());
  write_model_at(dir / "snapshot.ply", 40, 5);
  EXPECT_TRUE(model.refresh());
  EXPECT_EQ(model.gaussian_count(), 40u);
}

TEST(WatchedModel, WaitingForAFirstModelEndsWithAnError) {
  const fs::path dir = test::scratch_dir("watched_model_wait");
  EXPECT_THROW(wait_for_first_model(dir, 0.3), Error);
  EXPECT_THROW(wait_for_first_model(dir / "missing", 0.3), InputError);
  write_model_at(dir / "model.ply", 5, 1);
  EXPECT_NO_THROW(wait_for_first_model(dir, 0.3));
}

}  // namespace
}  // namespace splat::viewer
