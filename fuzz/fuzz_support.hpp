#pragma once
// What every fuzz target does: the readers take paths, as the tools call them, so the input
// is written to a file and read back. Only splat::Error may come out of a reader: an error
// the tools print as "error: FILE: what is wrong". Anything else is a finding: a crash or a
// sanitizer report, an exception of another kind (a library's raw message reaching the
// user), or memory beyond the run's limit (bench/fuzz.sh sets 1 GB).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "splat/core/error.hpp"

namespace splat::fuzz {

// A folder of this process's own under TMPDIR (libFuzzer may run several jobs side by side),
// removed when the process ends through exit(). libFuzzer's own ends (a finding, a timeout, the
// end of a replay) skip that, so bench/fuzz.sh and the replay tests point TMPDIR at folders of
// their own rather than /tmp.
class ScratchDir {
 public:
  ScratchDir() : path_(std::filesystem::temp_directory_path() / ("splat-fuzz-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline const std::filesystem::path& scratch_dir() {
  static const ScratchDir dir;
  return dir.path();
}

inline void write_bytes(const std::filesystem::path& file, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

// Writes the input to scratch_dir()/name and calls read(path); splat::Error is the expected
// way to refuse an input.
template <class Read>
int read_input_as(const char* name, const std::uint8_t* data, std::size_t size, const Read& read) {
  const std::filesystem::path file = scratch_dir() / name;
  write_bytes(file, data, size);
  try {
    read(file);
  } catch (const splat::Error&) {
  }
  return 0;
}

}  // namespace splat::fuzz
