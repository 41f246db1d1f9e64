#pragma once
// Reading a whole input file into memory, with the checks every reader makes first: the file
// exists, is a regular file, and is no larger than the reader can mean (a size limit turns a
// wrong or hostile file into a clear error before anything large is allocated).
#include <cstdint>
#include <filesystem>
#include <istream>
#include <vector>

namespace splat {

// The size of `file`. InputError naming it when it does not exist, is not a regular file
// (a folder, a device) or its size cannot be read.
std::uint64_t regular_file_size(const std::filesystem::path& file);

// Every byte of `file`. InputError as regular_file_size, and when it holds more than
// `max_bytes` (saying what `what` is, e.g. "a .splat model") or cannot be read.
std::vector<unsigned char> read_file_bytes(const std::filesystem::path& file, std::uint64_t max_bytes,
                                           const char* what);

// A reader that has consumed everything its header declares has consumed the file: bytes
// after that are a damaged, concatenated or wrongly-written file, not something to ignore.
// InputError "N bytes follow the end of `what`" when `in` is not at the end of `file`.
void expect_end_of_file(std::istream& in, const std::filesystem::path& file, const char* what);

}  // namespace splat
