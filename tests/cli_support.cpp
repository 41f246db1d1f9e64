#include "tests/cli_support.hpp"

#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

#include "splat/data/orbit_cameras.hpp"
#include "tests/rendered_dataset.hpp"
#include "splat/gaussians/demo_model.hpp"

namespace splat::test {

std::string read_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CommandResult run_command(const std::string& command, const std::filesystem::path& dir) {
  const auto out_file = dir / "stdout.txt", err_file = dir / "stderr.txt";
  const std::string full = command + " > " + out_file.string() + " 2> " + err_file.string() + " < /dev/null";
  const int status = std::system(full.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out_file);
  r.err = read_file(err_file);
  return r;
}

CheckpointParts split_checkpoint(const std::string& bytes) {
  std::uint64_t length = 0;
  std::memcpy(&length, bytes.data() + 12, sizeof(length));
  return {bytes.substr(0, 12), nlohmann::json::parse(bytes.substr(20, length)), bytes.substr(20 + length)};
}

std::string join_checkpoint(const CheckpointParts& parts) {
  const std::string header = parts.header.dump();
  const std::uint64_t length = header.size();
  std::string bytes = parts.prefix;
  bytes.append(reinterpret_cast<const char*>(&length), sizeof(length));
  return bytes + header + parts.arrays;
}

std::string last_line(const std::string& text) {
  std::string t = text;
  while (!t.empty() && (t.back() == '\n' || t.back() == '\r')) t.pop_back();
  const auto pos = t.rfind('\n');
  return pos == std::string::npos ? t : t.substr(pos + 1);
}

void write_demo_dataset(const std::filesystem::path& dir, int train_views, int test_views, int size,
                        std::size_t gaussians) {
  OrbitRig train_rig;
  train_rig.count = train_views;
  train_rig.radius = 5.5f;
  train_rig.width = train_rig.height = size;
  OrbitRig test_rig = train_rig;
  test_rig.count = test_views;
  test_rig.elevation_radians = 0.7f;
  const float white[3] = {1, 1, 1};
  write_rendered_dataset(make_demo_model(gaussians), orbit_cameras(train_rig), orbit_cameras(test_rig), white, dir);
}

bool have_tool(const std::string& name) {
  return std::system(("command -v " + name + " > /dev/null 2>&1").c_str()) == 0;
}

int video_frame_count(const std::filesystem::path& video) {
  const std::string cmd = "ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames "
                          "-of csv=p=0 " + video.string();
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  char line[64] = {};
  const bool read = std::fgets(line, sizeof(line), pipe) != nullptr;
  const int status = pclose(pipe);
  return read && status == 0 ? std::atoi(line) : -1;
}

}  // namespace splat::test
