#pragma once
// Parsing the text header of a PLY file into its format and element layout. Kept apart from
// the Gaussian-specific reading (ply_io.cpp) because it knows nothing about splats: it only
// turns "ply ... end_header" into types, sizes and byte offsets.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace splat::ply {

enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

enum class ScalarType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

// Bytes one value of `type` takes in a binary file.
std::size_t scalar_size(ScalarType type);
// The name a header uses for `type` ("float", "double", "uchar", ...), for messages.
std::string_view scalar_name(ScalarType type);

struct Property {
  std::string name;
  ScalarType type = ScalarType::kFloat32;  // for a list: the item type
  bool is_list = false;
  ScalarType list_count_type = ScalarType::kUint8;
  std::size_t offset = 0;  // byte offset within a binary row; meaningful only before any list
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;

  bool has_list() const;
  // Bytes of one binary row; only meaningful when !has_list().
  std::size_t row_bytes() const;
  const Property* find(std::string_view property_name) const;
};

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  std::size_t data_offset = 0;  // byte offset of the first data byte after "end_header\n"
};

// Headers larger than this are not PLY files written by any splat tool; the limits make
// garbage input fail fast instead of being scanned to its end.
constexpr std::size_t kMaxHeaderBytes = 64 * 1024;
constexpr std::size_t kMaxHeaderLines = 10000;

// Parses the header at the start of `bytes` (the first bytes of `file`, at most
// kMaxHeaderBytes are looked at). Throws InputError naming `file` on anything malformed.
Header parse_header(std::string_view bytes, const std::filesystem::path& file);

class LineCursor;

// A PLY file ends where its declared elements end: bytes beyond them are a damaged or
// concatenated file (InputError naming `file`), and so is data that stops inside one. Both
// check the elements after `last_read`, the one the reader stopped at. Binary rows that are
// lists (a mesh's faces) have no size without decoding them, which no reader of ours does:
// from such an element on, nothing more is checked. ASCII rows are one line each, and blank
// lines (as editors leave them) are not text.
void expect_binary_end(const Header& header, std::size_t last_read, std::uint64_t bytes_left,
                       const std::filesystem::path& file);
void expect_ascii_end(const Header& header, std::size_t last_read, LineCursor& cursor,
                      const std::filesystem::path& file);

}  // namespace splat::ply
