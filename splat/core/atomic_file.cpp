#include "splat/core/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <unistd.h>

#include "splat/core/error.hpp"

namespace splat {

void write_atomically(const std::filesystem::path& file,
                      const std::function<void(const std::filesystem::path&)>& write) {
  static std::atomic<unsigned> counter{0};
  // Unique per process and call, and the same extension as the target.
  const std::filesystem::path temp =
      file.parent_path() / (".tmp-" + std::to_string(::getpid()) + "-" +
                            std::to_string(counter++) + "-" + file.filename().string());
  try {
    write(temp);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(temp, file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw InputError(file, "cannot move the finished file into place: " + ec.message());
  }
}

void write_stream_atomically(const std::filesystem::path& file, const std::function<void(std::ostream& out)>& write) {
  write_atomically(file, [&](const std::filesystem::path& temp) {
    errno = 0;
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(file, "cannot create the file: " + std::string(std::strerror(errno)));
    write(out);
    out.flush();
    const int flush_error = errno;
    out.close();
    if (!out) throw InputError(file, "cannot write the file: " + std::string(std::strerror(errno ? errno : flush_error)));
  });
}

void check_output_file_path(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw InputError(file, "is a folder; the output must be a file");
}

}  // namespace splat
