#include "splat/data/point_cloud_ply.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/core/file_bytes.hpp"
#include "splat/core/ply_ascii.hpp"
#include "splat/core/ply_header.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

// A point cloud file beyond this is not one: 2²⁶ points of 15 doubles each as text.
constexpr std::uint64_t kMaxFileBytes = std::uint64_t(16) << 30;
constexpr float kNoColour = 0.5f;

template <typename T>
T load(const unsigned char* bytes, bool swap) {
  using Bits = std::conditional_t<sizeof(T) == 1, std::uint8_t,
                                  std::conditional_t<sizeof(T) == 2, std::uint16_t,
                                                     std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  Bits bits;
  std::memcpy(&bits, bytes, sizeof bits);
  if (swap) {  // (std::byteswap is C++23)
    Bits swapped = 0;
    for (std::size_t b = 0; b < sizeof bits; ++b) swapped = Bits((swapped << 8) | ((bits >> (8 * b)) & 0xFF));
    bits = swapped;
  }
  return std::bit_cast<T>(bits);
}

double binary_value(const unsigned char* bytes, ply::ScalarType type, bool swap) {
  switch (type) {
    case ply::ScalarType::kInt8: return load<std::int8_t>(bytes, swap);
    case ply::ScalarType::kUint8: return load<std::uint8_t>(bytes, swap);
    case ply::ScalarType::kInt16: return load<std::int16_t>(bytes, swap);
    case ply::ScalarType::kUint16: return load<std::uint16_t>(bytes, swap);
    case ply::ScalarType::kInt32: return load<std::int32_t>(bytes, swap);
    case ply::ScalarType::kUint32: return load<std::uint32_t>(bytes, swap);
    case ply::ScalarType::kFloat32: return load<float>(bytes, swap);
    case ply::ScalarType::kFloat64: return load<double>(bytes, swap);
  }
  return 0;
}

bool is_float(ply::ScalarType type) { return type == ply::ScalarType::kFloat32 || type == ply::ScalarType::kFloat64; }

// The properties read, by their index in the vertex element's row; -1 when absent.
struct Columns {
  int position[3] = {-1, -1, -1};
  int colour[3] = {-1, -1, -1};
};

Columns find_columns(const ply::Element& vertex, const fs::path& file) {
  Columns c;
  const char* position_names[3] = {"x", "y", "z"};
  const char* colour_names[3] = {"red", "green", "blue"};
  for (std::size_t j = 0; j < vertex.properties.size(); ++j) {
    const ply::Property& p = vertex.properties[j];
    for (int k = 0; k < 3; ++k) {
      if (p.name == position_names[k]) c.position[k] = int(j);
      if (p.name == colour_names[k]) c.colour[k] = int(j);
    }
  }
  for (int k = 0; k < 3; ++k)
    if (c.position[k] < 0)
      throw InputError(file, std::string("the vertex element has no '") + position_names[k] + "' property");
  return c;
}

// Puts row i's values (by property index) into the cloud.
void store_point(const Columns& c, const ply::Element& vertex, const std::vector<double>& row, std::size_t i,
                 PointCloud& cloud, const fs::path& file) {
  for (int k = 0; k < 3; ++k) {
    const double v = row[std::size_t(c.position[k])];
    if (!std::isfinite(v)) throw InputError(file, "point " + std::to_string(i) + " has a non-finite position");
    cloud.positions[3 * i + std::size_t(k)] = float(v);
    float colour = kNoColour;
    if (c.colour[k] >= 0) {
      const double raw = row[std::size_t(c.colour[k])];
      colour = float(is_float(vertex.properties[std::size_t(c.colour[k])].type) ? raw : raw / 255.0);
      colour = std::isfinite(colour) ? std::fmin(std::fmax(colour, 0.0f), 1.0f) : kNoColour;
    }
    cloud.colors[3 * i + std::size_t(k)] = colour;
  }
}

}  // namespace

PointCloud read_point_cloud_ply(const fs::path& file) {
  const std::vector<unsigned char> bytes = read_file_bytes(file, kMaxFileBytes, "a point cloud");
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const ply::Header header = ply::parse_header(text.substr(0, ply::kMaxHeaderBytes), file);
  std::size_t vertex_index = header.elements.size();
  for (std::size_t e = 0; e < header.elements.size(); ++e)
    if (header.elements[e].name == "vertex") vertex_index = e;
  if (vertex_index == header.elements.size()) throw InputError(file, "no 'vertex' element: not a point cloud");
  const ply::Element& vertex = header.elements[vertex_index];
  if (vertex.has_list()) throw InputError(file, "the vertex element has list properties: not a point cloud");
  const Columns columns = find_columns(vertex, file);
  if (vertex.count > kMaxPointCloudPoints)
    throw InputError(file, "declares " + std::to_string(vertex.count) + " points, more than the " +
                               std::to_string(kMaxPointCloudPoints) + " a point cloud may hold");

  const std::size_t values = vertex.properties.size();
  std::vector<double> row(values);
  PointCloud cloud;
  const std::size_t n = std::size_t(vertex.count);
  const std::string truncated = "truncated: the header declares " + std::to_string(n) + " points";
  if (header.format == ply::Format::kAscii) {
    ply::LineCursor cursor(text.substr(header.data_offset));
    std::string_view line;
    for (std::size_t e = 0; e < vertex_index; ++e)
      for (std::uint64_t r = 0; r < header.elements[e].count; ++r)
        if (!cursor.next(line)) throw InputError(file, truncated);
    // Each value takes a character and a separator at least: an impossible count fails here.
    if (n > (cursor.remaining() + 1) / (2 * values)) throw InputError(file, truncated);
    cloud.positions.resize(3 * n);
    cloud.colors.resize(3 * n);
    std::vector<std::string_view> words;
    for (std::size_t i = 0; i < n; ++i) {
      if (!cursor.next(line) || ply::split_values(line, words, values) != values)
        throw InputError(file, "point " + std::to_string(i) + ": expected " + std::to_string(values) + " values");
      for (std::size_t j = 0; j < values; ++j)
        if (!ply::parse_number(words[j], row[j]))
          throw InputError(file, "point " + std::to_string(i) + ": '" + std::string(words[j].substr(0, 40)) +
                                     "' is not a number");
      store_point(columns, vertex, row, i, cloud, file);
    }
    ply::expect_ascii_end(header, vertex_index, cursor, file);
    return cloud;
  }
  std::uint64_t offset = header.data_offset;
  for (std::size_t e = 0; e < vertex_index; ++e) {
    const ply::Element& before = header.elements[e];
    if (before.has_list())
      throw InputError(file, "element '" + before.name + "' before the vertices has list properties; not supported");
    offset += before.count * before.row_bytes();
    if (offset > bytes.size()) throw InputError(file, truncated);
  }
  const std::size_t stride = vertex.row_bytes();
  if (n > (bytes.size() - offset) / stride) throw InputError(file, truncated);
  ply::expect_binary_end(header, vertex_index, bytes.size() - offset - n * stride, file);
  const bool swap = (header.format == ply::Format::kBinaryLittleEndian) != (std::endian::native == std::endian::little);
  cloud.positions.resize(3 * n);
  cloud.colors.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* at = bytes.data() + offset + i * stride;
    for (std::size_t j = 0; j < values; ++j)
      row[j] = binary_value(at + vertex.properties[j].offset, vertex.properties[j].type, swap);
    store_point(columns, vertex, row, i, cloud, file);
  }
  return cloud;
}

}  // namespace splat
