#include "apps/common/video_writer.hpp"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"

extern char** environ;

namespace splat::cli {
namespace {

// How much of ffmpeg's error output an error message quotes: its last lines say what failed.
constexpr std::size_t kStderrTailBytes = 600;

// The encoder arguments for each container we write.
std::optional<std::vector<std::string>> codec_arguments(const std::filesystem::path& file) {
  const std::string extension = file.extension().string();
  if (extension == ".mp4" || extension == ".mkv") return std::vector<std::string>{"-c:v", "libx264", "-crf", "18"};
  if (extension == ".webm") return std::vector<std::string>{"-c:v", "libvpx-vp9", "-crf", "30", "-b:v", "0"};
  return std::nullopt;
}

// The last kStderrTailBytes of what ffmpeg wrote to `fd`, on one line.
std::string stderr_tail(int fd) {
  std::string text;
  if (fd >= 0 && ::lseek(fd, 0, SEEK_SET) == 0) {
    char buffer[4096];
    for (ssize_t n; (n = ::read(fd, buffer, sizeof(buffer))) > 0;) text.append(buffer, std::size_t(n));
  }
  if (text.size() > kStderrTailBytes) text = "..." + text.substr(text.size() - kStderrTailBytes);
  std::string line;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!line.empty() && line.back() != ' ') line += "; ";
    } else {
      line += c;
    }
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  return line.empty() ? "(no message)" : line;
}

std::string exit_description(int status) {
  if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "status " + std::to_string(status);
}

}  // namespace

std::optional<std::filesystem::path> find_ffmpeg() {
  const char* path = std::getenv("PATH");
  std::string entries = path ? path : "";
  std::size_t begin = 0;
  while (begin <= entries.size()) {
    std::size_t end = entries.find(':', begin);
    if (end == std::string::npos) end = entries.size();
    const std::string dir = entries.substr(begin, end - begin);
    const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / "ffmpeg";
    if (::access(candidate.c_str(), X_OK) == 0 && !std::filesystem::is_directory(candidate)) return candidate;
    begin = end + 1;
  }
  return std::nullopt;
}

std::string video_extension_problem(const std::filesystem::path& file) {
  if (codec_arguments(file)) return "";
  return "cannot write a '" + file.extension().string() + "' video (splat-render writes .mp4, .mkv and .webm)";
}

VideoWriter::VideoWriter(const std::filesystem::path& ffmpeg, const std::filesystem::path& file,
                         const std::filesystem::path& temp, int width, int height, double fps)
    : file_(file), width_(width), height_(height) {
  if (width % 2 != 0 || height % 2 != 0)
    throw ArgumentError("a video's width and height must be even (4:2:0 colour), not " + std::to_string(width) +
                        "x" + std::to_string(height));
  const auto codec = codec_arguments(file);
  if (!codec) throw InputError(file, video_extension_problem(file));
  // A write to a pipe whose reader has gone must fail with EPIPE, not kill us: we then wait
  // for ffmpeg and report what it said.
  std::signal(SIGPIPE, SIG_IGN);

  char rate[32];
  std::snprintf(rate, sizeof(rate), "%.6g", fps);
  std::vector<std::string> args = {ffmpeg.string(), "-hide_banner", "-loglevel", "error", "-f", "rawvideo",
                                   "-pix_fmt", "rgb24", "-video_size",
                                   std::to_string(width) + "x" + std::to_string(height), "-framerate", rate,
                                   "-i", "pipe:0", "-an"};
  args.insert(args.end(), codec->begin(), codec->end());
  for (const char* a : {"-pix_fmt", "yuv420p", "-y"}) args.emplace_back(a);
  args.push_back(temp.string());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw InputError(file, std::string("cannot open a pipe to ffmpeg: ") + std::strerror(errno));
  stderr_fd_ = ::memfd_create("ffmpeg-stderr", MFD_CLOEXEC);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  if (stderr_fd_ >= 0) posix_spawn_file_actions_adddup2(&actions, stderr_fd_, STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);  // ffmpeg gets the usual SIGPIPE, not our ignoring it
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
  const int spawned = ::posix_spawn(&pid_, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(fds[0]);
  if (spawned != 0) {
    pid_ = -1;
    ::close(fds[1]);
    throw InputError(file, "cannot start " + ffmpeg.string() + ": " + std::strerror(spawned));
  }
  pipe_fd_ = fds[1];
}

VideoWriter::~VideoWriter() { stop(); }

void VideoWriter::stop() {
  if (pipe_fd_ >= 0) ::close(pipe_fd_);
  pipe_fd_ = -1;
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {}
    pid_ = -1;
  }
  if (stderr_fd_ >= 0) ::close(stderr_fd_);
  stderr_fd_ = -1;
}

int VideoWriter::close_and_wait() {
  if (pipe_fd_ >= 0) ::close(pipe_fd_);  // end of stream: ffmpeg finishes the file and exits
  pipe_fd_ = -1;
  int code = 0;
  if (pid_ > 0) {
    while (::waitpid(pid_, &code, 0) < 0 && errno == EINTR) {}
    pid_ = -1;
  }
  return code;
}

void VideoWriter::fail(int code) {
  const std::string tail = stderr_tail(stderr_fd_);
  stop();
  throw InputError(file_, "ffmpeg failed (" + exit_description(code) + "): " + tail);
}

void VideoWriter::write(const Image& frame) {
  if (frame.width != width_ || frame.height != height_ || frame.channels != 3)
    throw ArgumentError("VideoWriter: frames must be " + std::to_string(width_) + "x" + std::to_string(height_) + " RGB");
  if (pipe_fd_ < 0) throw ArgumentError("VideoWriter: write after finish");
  const std::vector<std::uint8_t> codes = image_codes_8bit(frame);
  std::size_t sent = 0;
  while (sent < codes.size()) {
    const ssize_t n = ::write(pipe_fd_, codes.data() + sent, codes.size() - sent);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(close_and_wait());  // ffmpeg has stopped reading (EPIPE): say why
    sent += std::size_t(n);
  }
}

void VideoWriter::finish() {
  if (pipe_fd_ < 0) throw ArgumentError("VideoWriter: finished twice");
  const int code = close_and_wait();
  if (!WIFEXITED(code) || WEXITSTATUS(code) != 0) fail(code);
  stop();
}

}  // namespace splat::cli
