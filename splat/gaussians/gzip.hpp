#pragma once
// gzip streams through zlib, for the .spz model format (a gzipped byte layout).
#include <cstddef>
#include <filesystem>
#include <span>
#include <vector>

namespace splat {

// The gzip stream (one member, zlib's default level) of `bytes`.
std::vector<unsigned char> gzip(std::span<const unsigned char> bytes);

// The bytes a gzip stream inflates to. `file` names errors: InputError when the data is not
// gzip, is corrupt or ends early, has bytes after the end of the stream, or inflates to more
// than `max_bytes` (checked while inflating, so a small file that claims gigabytes fails fast).
std::vector<unsigned char> gunzip(std::span<const unsigned char> compressed, std::size_t max_bytes,
                                  const std::filesystem::path& file);

// The first `count` bytes the stream inflates to (all of them when it is shorter), for a
// reader that sizes the rest from a header. InputError when the data is not gzip or corrupt
// before `count` bytes.
std::vector<unsigned char> gunzip_prefix(std::span<const unsigned char> compressed, std::size_t count,
                                         const std::filesystem::path& file);

}  // namespace splat
