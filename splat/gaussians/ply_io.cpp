#include "splat/gaussians/ply_io.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/core/file_bytes.hpp"
#include "splat/gaussians/byte_quantization.hpp"
#include "splat/core/ply_ascii.hpp"
#include "splat/core/ply_header.hpp"

namespace splat {
namespace {

constexpr std::string_view kVertexElement = "vertex";
constexpr std::string_view kRestPrefix = "f_rest_";
constexpr std::size_t kFloatBytes = sizeof(float);
constexpr int kColorChannels = 3;
static_assert(sizeof(float) == sizeof(std::uint32_t));

}  // namespace

std::vector<PlyColumn> official_ply_columns(int sh_degree) {
  const std::size_t k_count = static_cast<std::size_t>(sh_coefficient_count(sh_degree));
  std::vector<PlyColumn> columns;
  // Value `first` of each row of group `id`.
  const auto add = [&](std::string name, ParameterGroupId id, std::size_t first) {
    const ParameterGroup& group = parameter_group(id);
    columns.push_back({std::move(name), group.values, first, group.width(sh_degree)});
  };
  const char* const axes[] = {"x", "y", "z"};
  for (std::size_t a = 0; a < 3; ++a) add(axes[a], ParameterGroupId::kMeans, a);
  for (const char* normal : {"nx", "ny", "nz"}) columns.push_back({normal, nullptr, 0, 0});
  for (std::size_t c = 0; c < kColorChannels; ++c) add("f_dc_" + std::to_string(c), ParameterGroupId::kSh, c);
  // The file is channel-major (all of red's higher bands, then green's, ...); the model keeps
  // RGB innermost, so f_rest index c * (K-1) + (k-1) is model coefficient k, channel c.
  for (std::size_t c = 0; c < kColorChannels; ++c)
    for (std::size_t k = 1; k < k_count; ++k)
      add(std::string(kRestPrefix) + std::to_string(c * (k_count - 1) + (k - 1)), ParameterGroupId::kSh,
          k * kColorChannels + c);
  add("opacity", ParameterGroupId::kOpacityLogits, 0);
  for (std::size_t a = 0; a < 3; ++a) add("scale_" + std::to_string(a), ParameterGroupId::kLogScales, a);
  for (std::size_t a = 0; a < 4; ++a) add("rot_" + std::to_string(a), ParameterGroupId::kQuats, a);
  return columns;
}

namespace {

bool is_rest_property(std::string_view name) {
  if (!name.starts_with(kRestPrefix) || name.size() == kRestPrefix.size()) return false;
  for (char c : name.substr(kRestPrefix.size()))
    if (c < '0' || c > '9') return false;
  return true;
}

// The SH degree whose higher bands need `rest_count` f_rest properties, or -1.
int degree_for_rest_count(std::size_t rest_count) {
  for (int degree = 0; degree <= kMaxShDegree; ++degree)
    if (rest_count == std::size_t(kColorChannels) * (sh_coefficient_count(degree) - 1))
      return degree;
  return -1;
}

// A required property resolved to its place in the file and in the (allocated) model.
struct Target {
  const ply::Property* property;
  float* dst;
  std::size_t stride;
};

// Everything read_ply needs to know about the vertex element before touching its data.
struct VertexLayout {
  std::size_t element_index = 0;
  int sh_degree = 0;
  std::vector<PlyColumn> columns;                 // required columns (normals dropped)
  std::vector<const ply::Property*> sources;   // sources[j] is where columns[j] comes from
};

// PLY files of other kinds that users hand a splat tool, told apart by what they hold, so the
// message says what the file is rather than which property it lacks.
void reject_other_layouts(const ply::Header& header, const ply::Element& vertex, const std::filesystem::path& file) {
  const bool has_chunks = std::any_of(header.elements.begin(), header.elements.end(),
                                      [](const ply::Element& e) { return e.name == "chunk"; });
  if (has_chunks || vertex.find("packed_position") != nullptr)
    throw InputError(file, "a compressed PLY (the SuperSplat / splat-transform layout), not the 3DGS PLY; convert "
                           "it with `npx @playcanvas/splat-transform " + file.filename().string() +
                               " model.ply` (or to .spz with --spz-version 3, or .splat: both are read)");
  // A 3DGS file missing some of these is named by the property it lacks (below).
  for (const char* gaussian_property : {"f_dc_0", "opacity", "scale_0", "rot_0"})
    if (vertex.find(gaussian_property) != nullptr) return;
  const bool has_faces = std::any_of(header.elements.begin(), header.elements.end(),
                                     [](const ply::Element& e) { return e.name == "face"; });
  const std::string what = has_faces ? "a mesh PLY (it has faces)" : "a point-cloud PLY";
  throw InputError(file, what + ", not a 3DGS model: its vertices have none of the Gaussian properties (f_dc_0, opacity, "
                                "scale_0, rot_0)");
}

VertexLayout resolve_vertex_layout(const ply::Header& header, const std::filesystem::path& file) {
  VertexLayout layout;
  const ply::Element* vertex = nullptr;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    if (header.elements[e].name == kVertexElement) {
      vertex = &header.elements[e];
      layout.element_index = e;
    }
  }
  if (vertex == nullptr) throw InputError(file, "PLY file has no 'vertex' element");
  reject_other_layouts(header, *vertex, file);
  for (const ply::Property& p : vertex->properties)
    if (p.is_list)
      throw InputError(file, "vertex property '" + p.name +
                                 "' is a list; the 3DGS layout has only scalar properties");

  std::size_t rest_count = 0;
  for (const ply::Property& p : vertex->properties)
    if (is_rest_property(p.name)) ++rest_count;
  layout.sh_degree = degree_for_rest_count(rest_count);
  if (layout.sh_degree < 0)
    throw InputError(file, "unsupported number of f_rest properties: " +
                               std::to_string(rest_count) +
                               " (expected 0, 9, 24 or 45 for SH degree 0 to 3)");

  for (PlyColumn& column : official_ply_columns(layout.sh_degree)) {
    if (column.array == nullptr) continue;
    const ply::Property* p = vertex->find(column.name);
    if (p == nullptr)
      throw InputError(file, "missing required vertex property '" + column.name + "'");
    if (p->type != ply::ScalarType::kFloat32)
      throw InputError(file, "vertex property '" + column.name + "' has type " +
                                 std::string(ply::scalar_name(p->type)) +
                                 "; the 3DGS layout needs float");
    layout.columns.push_back(std::move(column));
    layout.sources.push_back(p);
  }
  return layout;
}

void check_gaussian_count(std::uint64_t count, const std::filesystem::path& file) {
  if (count > kMaxGaussiansInAFile)
    throw InputError(file, "the header declares " + std::to_string(count) + " Gaussians, more than the " +
                               std::to_string(kMaxGaussiansInAFile) + " a model file may hold");
}

std::vector<Target> bind_targets(const VertexLayout& layout, GaussianModel& model) {
  std::vector<Target> targets;
  targets.reserve(layout.columns.size());
  for (std::size_t j = 0; j < layout.columns.size(); ++j) {
    const PlyColumn& c = layout.columns[j];
    // An empty model's arrays have no storage: offsetting their null pointer is undefined.
    std::vector<float>& array = model.*c.array;
    targets.push_back({layout.sources[j], array.empty() ? nullptr : array.data() + c.first, c.stride});
  }
  return targets;
}

// Whether `value` of property `p` can be kept, made finite where it stands for a definite
// opacity: Niantic's .spz decoder (and so splat-transform's PLY output) writes the opacity
// logit of opacity bytes 255 and 0 as ±Inf. They read as our .spz reader reads those bytes.
bool keep_value(const ply::Property& p, float& value) {
  if (std::isfinite(value)) return true;
  if (!std::isinf(value) || p.name != "opacity") return false;
  value = opacity_logit_from_byte(value > 0 ? 255 : 0);
  return true;
}

[[noreturn]] void throw_not_finite(const std::filesystem::path& file, std::size_t vertex,
                                   const ply::Property& p, float value) {
  throw InputError(file, "vertex " + std::to_string(vertex) + ", property '" + p.name + "' is " +
                             (std::isnan(value) ? "NaN" : "infinite (Inf)"));
}

std::string truncated_message(std::uint64_t count, std::string_view element, std::size_t row_bytes,
                              std::uint64_t available) {
  return "data is truncated: the header declares " + std::to_string(count) + " " +
         std::string(element) + " rows of " + std::to_string(row_bytes) + " bytes but only " +
         std::to_string(available) + " bytes of data follow the header";
}

// Binary reading: one read of the whole vertex block, then fixed-offset memcpy decoding.
GaussianModel read_binary(std::ifstream& in, std::uint64_t file_size, const ply::Header& header,
                          const VertexLayout& layout, const std::filesystem::path& file) {
  std::uint64_t available = file_size - header.data_offset;
  std::uint64_t skip = 0;
  for (std::size_t e = 0; e < layout.element_index; ++e) {
    const ply::Element& before = header.elements[e];
    if (before.has_list())
      throw InputError(file, "element '" + before.name +
                                 "' before the vertex element has list properties; "
                                 "such binary PLY files are not supported");
    const std::size_t row = before.row_bytes();
    if (row != 0 && before.count > (available - skip) / row)
      throw InputError(file, truncated_message(before.count, before.name, row, available - skip));
    skip += before.count * row;
  }
  available -= skip;

  const ply::Element& vertex = header.elements[layout.element_index];
  const std::size_t stride = vertex.row_bytes();  // > 0: at least the required floats
  // Checked against the real file size before anything is allocated, so a header that claims
  // billions of vertices fails here instead of exhausting memory.
  check_gaussian_count(vertex.count, file);
  if (vertex.count > available / stride)
    throw InputError(file, truncated_message(vertex.count, kVertexElement, stride, available));
  const std::size_t n = static_cast<std::size_t>(vertex.count);

  ply::expect_binary_end(header, layout.element_index, available - n * stride, file);

  std::vector<unsigned char> payload(n * stride);
  in.seekg(static_cast<std::streamoff>(header.data_offset + skip));
  in.read(reinterpret_cast<char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
  if (static_cast<std::size_t>(in.gcount()) != payload.size())
    throw InputError(file, "read error in the vertex data");

  GaussianModel model;
  model.sh_degree = layout.sh_degree;
  model.resize(n);
  const std::vector<Target> targets = bind_targets(layout, model);
  const bool swap = (header.format == ply::Format::kBinaryLittleEndian) !=
                    (std::endian::native == std::endian::little);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* row = payload.data() + i * stride;
    for (const Target& t : targets) {
      std::uint32_t bits;
      std::memcpy(&bits, row + t.property->offset, kFloatBytes);
      if (swap) bits = __builtin_bswap32(bits);
      const float value = std::bit_cast<float>(bits);
      float kept = value;
      if (!keep_value(*t.property, kept)) throw_not_finite(file, i, *t.property, value);
      t.dst[i * t.stride] = kept;
    }
  }
  return model;
}

GaussianModel read_ascii(std::ifstream& in, std::uint64_t file_size, const ply::Header& header,
                         const VertexLayout& layout, const std::filesystem::path& file) {
  // The text is bounded by the real file size, so this allocation is as large as the file.
  std::string text(static_cast<std::size_t>(file_size - header.data_offset), '\0');
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (static_cast<std::size_t>(in.gcount()) != text.size())
    throw InputError(file, "read error in the ASCII data");
  ply::LineCursor cursor(text);
  std::string_view line;

  // ASCII rows are one line each whatever their properties, lists included.
  for (std::size_t e = 0; e < layout.element_index; ++e) {
    const ply::Element& before = header.elements[e];
    for (std::uint64_t r = 0; r < before.count; ++r)
      if (!cursor.next(line))
        throw InputError(file, "ASCII data is truncated: it ends inside element '" +
                                   before.name + "'");
  }

  const ply::Element& vertex = header.elements[layout.element_index];
  const std::size_t values_per_row = vertex.properties.size();
  // Each value takes at least one character and one separator: reject impossible counts
  // before allocating.
  const std::uint64_t max_rows = (cursor.remaining() + 1) / (2 * values_per_row);
  check_gaussian_count(vertex.count, file);
  if (vertex.count > max_rows)
    throw InputError(file, "ASCII data is truncated: the header declares " +
                               std::to_string(vertex.count) + " vertices but the data has room "
                               "for at most " + std::to_string(max_rows));
  const std::size_t n = static_cast<std::size_t>(vertex.count);

  GaussianModel model;
  model.sh_degree = layout.sh_degree;
  model.resize(n);
  // By property index: the target the value goes to, or nullptr for a property we skip.
  std::vector<const Target*> by_index(values_per_row, nullptr);
  const std::vector<Target> targets = bind_targets(layout, model);
  for (const Target& t : targets) by_index[t.property - vertex.properties.data()] = &t;

  std::vector<std::string_view> words;
  for (std::size_t i = 0; i < n; ++i) {
    if (!cursor.next(line))
      throw InputError(file, "ASCII data is truncated: it ends after " + std::to_string(i) +
                                 " of " + std::to_string(n) + " vertices");
    const std::size_t count = ply::split_values(line, words, values_per_row);
    if (count != values_per_row)
      throw InputError(file, "ASCII vertex " + std::to_string(i) + " has " +
                                 (count > values_per_row ? "more than " : "") +
                                 std::to_string(count) + " values, expected " +
                                 std::to_string(values_per_row));
    for (std::size_t j = 0; j < values_per_row; ++j) {
      const ply::Property& p = vertex.properties[j];
      bool ok;
      if (const Target* t = by_index[j]) {
        float value;
        ok = ply::parse_number(words[j], value);
        if (ok && !keep_value(p, value)) throw_not_finite(file, i, p, value);
        if (ok) t->dst[i * t->stride] = value;
      } else {
        double ignored;
        ok = ply::parse_number(words[j], ignored);
      }
      if (!ok)
        throw InputError(file, "ASCII vertex " + std::to_string(i) + ", property '" + p.name +
                                   "': '" + std::string(words[j].substr(0, 40)) +
                                   "' is not a number");
    }
  }
  ply::expect_ascii_end(header, layout.element_index, cursor, file);
  return model;
}

void append_little_endian(unsigned char*& out, float value) {
  std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
  if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
  std::memcpy(out, &bits, kFloatBytes);
  out += kFloatBytes;
}

}  // namespace

GaussianModel read_ply(const std::filesystem::path& file) {
  const std::uint64_t file_size = regular_file_size(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "cannot open the file for reading");

  // The header lies within the first kMaxHeaderBytes; parse_header rejects it otherwise.
  const std::uint64_t head_size = std::min<std::uint64_t>(file_size, ply::kMaxHeaderBytes);
  std::string head(static_cast<std::size_t>(head_size), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (static_cast<std::size_t>(in.gcount()) != head.size())
    throw InputError(file, "read error in the PLY header");
  const ply::Header header = ply::parse_header(head, file);
  const VertexLayout layout = resolve_vertex_layout(header, file);
  GaussianModel model = header.format == ply::Format::kAscii ? read_ascii(in, file_size, header, layout, file)
                                                              : read_binary(in, file_size, header, layout, file);
  // A rotation is the normalised quaternion: one of length zero has none (the .splat reader
  // refuses the same).
  for (std::size_t i = 0; i < model.size(); ++i)
    if (std::all_of(model.quats.begin() + std::ptrdiff_t(4 * i), model.quats.begin() + std::ptrdiff_t(4 * i + 4),
                    [](float q) { return q == 0.0f; }))
      throw InputError(file, "vertex " + std::to_string(i) + " has a rotation of length zero (rot_0..3 all 0)");
  return model;
}

void write_ply(const GaussianModel& model, const std::filesystem::path& file) {
  model.check_consistent();
  const std::vector<PlyColumn> columns = official_ply_columns(model.sh_degree);
  const std::size_t n = model.size();

  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                       std::to_string(n) + "\n";
  for (const PlyColumn& c : columns) header += "property float " + c.name + "\n";
  header += "end_header\n";

  std::vector<unsigned char> payload(n * columns.size() * kFloatBytes);
  unsigned char* out = payload.data();
  for (std::size_t i = 0; i < n; ++i)
    for (const PlyColumn& c : columns)
      append_little_endian(out, c.array ? (model.*c.array)[c.first + i * c.stride] : 0.0f);

  write_stream_atomically(file, [&](std::ostream& stream) {
    stream.write(header.data(), static_cast<std::streamsize>(header.size()));
    stream.write(reinterpret_cast<const char*>(payload.data()),
                 static_cast<std::streamsize>(payload.size()));
  });
}

}  // namespace splat
