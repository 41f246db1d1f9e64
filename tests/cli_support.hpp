#pragma once
// Running the command-line tools from tests.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace splat::test {

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `command` through the shell with stdout and stderr captured in files under `dir`.
CommandResult run_command(const std::string& command, const std::filesystem::path& dir);

std::string read_file(const std::filesystem::path& file);

// The last non-empty line of `text`.
std::string last_line(const std::string& text);

// A small Blender-style dataset of the demo model (`gaussians` of them) written into `dir`:
// `train_views` on an orbit of radius 5.5 and `test_views` on one higher up, at size × size,
// on white. What the trainer and splat-eval tests train on.
// Whether `name` is a program on PATH.
bool have_tool(const std::string& name);
// The frames ffprobe decodes from the video's first stream, or -1 when it cannot read it.
int video_frame_count(const std::filesystem::path& video);

#define SPLAT_SKIP_WITHOUT_FFMPEG()                                                              \
  if (!splat::test::have_tool("ffmpeg") || !splat::test::have_tool("ffprobe"))                   \
  GTEST_SKIP() << "ffmpeg/ffprobe are not installed (scripts/install-deps.sh installs them)"

void write_demo_dataset(const std::filesystem::path& dir, int train_views, int test_views, int size,
                        std::size_t gaussians);

// A splat-train checkpoint in its parts, for tests that damage one:
// "SPLATCKP" | u32 version | u64 header length | header JSON | arrays.
struct CheckpointParts {
  std::string prefix;  // magic and version
  nlohmann::json header;
  std::string arrays;
};
CheckpointParts split_checkpoint(const std::string& bytes);
std::string join_checkpoint(const CheckpointParts& parts);

}  // namespace splat::test
