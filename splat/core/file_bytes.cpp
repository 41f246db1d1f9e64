#include "splat/core/file_bytes.hpp"

#include <fstream>
#include <string>
#include <system_error>

#include "splat/core/error.hpp"

namespace splat {

std::uint64_t regular_file_size(const std::filesystem::path& file) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw InputError(file, "file does not exist");
  if (ec) throw InputError(file, "cannot access the file: " + ec.message());
  if (!std::filesystem::is_regular_file(status)) throw InputError(file, "not a regular file");
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  if (ec) throw InputError(file, "cannot get the file size: " + ec.message());
  return size;
}

std::vector<unsigned char> read_file_bytes(const std::filesystem::path& file, std::uint64_t max_bytes,
                                           const char* what) {
  const std::uint64_t size = regular_file_size(file);
  if (size > max_bytes)
    throw InputError(file, "the file holds " + std::to_string(size) + " bytes, more than " + what +
                               " may (" + std::to_string(max_bytes) + ")");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "cannot open the file for reading");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::uint64_t>(in.gcount()) != size) throw InputError(file, "read error");
  return bytes;
}

void expect_end_of_file(std::istream& in, const std::filesystem::path& file, const char* what) {
  if (in.peek() == std::char_traits<char>::eof()) {
    in.clear();  // peek at the end sets eofbit; the stream was read whole
    return;
  }
  const std::streamoff at = in.tellg();
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  const std::string count = ec || at < 0 ? "bytes" : std::to_string(size - std::uint64_t(at)) + " bytes";
  throw InputError(file, count + " follow the end of " + what);
}

}  // namespace splat
