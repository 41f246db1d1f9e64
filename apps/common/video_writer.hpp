#pragma once
// Video files through ffmpeg: frames go down a pipe as raw 8-bit RGB, ffmpeg encodes them
// (H.264 in .mp4/.mkv, VP9 in .webm, 4:2:0 so every player shows them). We run it rather than
// link libav*: one subprocess, no codec libraries in the build.
#include <filesystem>
#include <optional>
#include <string>
#include <sys/types.h>

#include "splat/core/image.hpp"

namespace splat::cli {

// ffmpeg's full path if it is on the PATH, else nothing.
std::optional<std::filesystem::path> find_ffmpeg();

// "" when `file`'s extension names a container we encode, else what is wrong (naming the
// ones we do).
std::string video_extension_problem(const std::filesystem::path& file);

class VideoWriter {
 public:
  // Starts `ffmpeg` writing `temp` (write_atomically's name for `file`, which errors name; the
  // container from the extension), width x height at `fps` frames per second; both sides
  // must be even (4:2:0 halves the colour planes). InputError when ffmpeg cannot start.
  VideoWriter(const std::filesystem::path& ffmpeg, const std::filesystem::path& file,
              const std::filesystem::path& temp, int width, int height, double fps);
  // Unfinished (an error on the way): stops ffmpeg and waits for it, so the caller can
  // remove its half-written file.
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Sends one RGB frame of the writer's size (values clamped to [0, 1] and rounded, as PNGs
  // are). When ffmpeg has stopped: InputError naming the file, with the end of ffmpeg's errors.
  void write(const Image& frame);
  // Ends the stream and waits for ffmpeg to finish the file; InputError as write() when it
  // fails.
  void finish();

 private:
  int close_and_wait();               // ends the stream; ffmpeg's wait status
  [[noreturn]] void fail(int status);  // InputError with the status and ffmpeg's last words
  void stop();                         // kills ffmpeg if still running, closes everything

  std::filesystem::path file_;
  int width_, height_;
  pid_t pid_ = -1;
  int pipe_fd_ = -1;     // ffmpeg's stdin
  int stderr_fd_ = -1;   // an anonymous file ffmpeg's stderr goes to, read back on failure
};

}  // namespace splat::cli
