#include "splat/gaussians/spz_file.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/core/file_bytes.hpp"
#include "splat/gaussians/axis_flip.hpp"
#include "splat/gaussians/byte_quantization.hpp"
#include "splat/gaussians/gzip.hpp"

namespace splat {
namespace {

static_assert(std::endian::native == std::endian::little, "the .spz reader and writer assume a little-endian host");

constexpr std::size_t kHeaderBytes = 16;
constexpr std::size_t kMeanBytes = 9;  // three 24-bit integers
constexpr int kMostFractionalBits = 16;
constexpr std::int32_t kLargestFixedPoint = (1 << 23) - 1;
constexpr float kColorScale = 0.15f;      // f_dc per unit of colour byte / 255, Niantic's choice
constexpr float kLogScaleOffset = 10.0f;  // scale bytes hold 16·(log scale + 10)
constexpr float kLogScaleSteps = 16.0f;
constexpr std::uint8_t kFlagExtensions = 0x2;
const float kSqrtHalf = std::sqrt(0.5f);

struct Header {
  std::uint32_t magic, version, count;
  std::uint8_t sh_degree, fractional_bits, flags, reserved;
};
static_assert(sizeof(Header) == kHeaderBytes);

// Bytes per Gaussian after the header, for a rotation of `rotation_bytes` bytes.
std::size_t record_bytes(int sh_degree, std::size_t rotation_bytes) {
  return kMeanBytes + 1 + 3 + 3 + rotation_bytes + 3 * std::size_t(sh_coefficient_count(sh_degree) - 1);
}

int fractional_bits_for(const GaussianModel& model) {
  float largest = 0;
  for (float v : model.means) largest = std::max(largest, std::abs(v));
  if (!(largest <= float(kLargestFixedPoint)))
    throw ArgumentError(".spz stores coordinates up to ±" + std::to_string(kLargestFixedPoint) +
                        "; this model has one of " + std::to_string(largest));
  int bits = kMostFractionalBits;
  while (bits > 0 && std::round(largest * float(1 << bits)) > float(kLargestFixedPoint)) --bits;
  return bits;
}

std::uint8_t quantize_sh(float value, int bits) {
  const int bucket = 1 << (8 - bits);
  int q = int(std::round(value * 128.0f)) + 128;
  q = (q + bucket / 2) / bucket * bucket;
  return static_cast<std::uint8_t>(std::clamp(q, 0, 255));
}

// The unit quaternion (w, x, y, z) as spz's "smallest three": spz orders it (x, y, z, w).
std::uint32_t pack_smallest_three(const Vec4<float>& wxyz) {
  const Vec4<float> u = unit_quaternion(wxyz);
  const float q[4] = {u[1], u[2], u[3], u[0]};
  int largest = 0;
  for (int i = 1; i < 4; ++i)
    if (std::abs(q[i]) > std::abs(q[largest])) largest = i;
  // q and −q are the same rotation: the largest is made positive and not stored.
  const bool negate = q[largest] < 0;
  std::uint32_t packed = std::uint32_t(largest);
  for (int i = 0; i < 4; ++i) {
    if (i == largest) continue;
    const std::uint32_t sign = (q[i] < 0) != negate ? 1u : 0u;
    const std::uint32_t magnitude = std::min(511u, std::uint32_t(std::round(511.0f * std::abs(q[i]) / kSqrtHalf)));
    packed = (packed << 10) | (sign << 9) | magnitude;
  }
  return packed;
}

Vec4<float> unpack_smallest_three(std::uint32_t packed) {
  const int largest = int(packed >> 30);
  float q[4];
  float sum_of_squares = 0;
  for (int i = 3; i >= 0; --i) {
    if (i == largest) continue;
    const float magnitude = kSqrtHalf * float(packed & 511u) / 511.0f;
    q[i] = (packed >> 9) & 1u ? -magnitude : magnitude;
    sum_of_squares += q[i] * q[i];
    packed >>= 10;
  }
  q[largest] = std::sqrt(std::max(0.0f, 1.0f - sum_of_squares));
  return {q[3], q[0], q[1], q[2]};
}

Vec4<float> unpack_first_three(const std::uint8_t* bytes) {
  float xyz[3], sum_of_squares = 0;
  for (int a = 0; a < 3; ++a) {
    xyz[a] = float(bytes[a]) / 127.5f - 1.0f;
    sum_of_squares += xyz[a] * xyz[a];
  }
  return {std::sqrt(std::max(0.0f, 1.0f - sum_of_squares)), xyz[0], xyz[1], xyz[2]};
}

Header read_header(std::span<const unsigned char> compressed, const std::filesystem::path& file) {
  // Version 4 files start with the magic itself: the header is not gzipped, the attributes are.
  if (compressed.size() >= 8 && std::memcmp(compressed.data(), &kSpzMagic, 4) == 0) {
    std::uint32_t version;
    std::memcpy(&version, compressed.data() + 4, 4);
    if (version <= 3)
      throw InputError(file, "a .spz of version " + std::to_string(version) + " that is not gzip-compressed");
    throw InputError(file, ".spz version " + std::to_string(version) +
                               " (attributes compressed one by one) is not read yet; write version 3 "
                               "(splat-transform IN --spz-version 3 OUT.spz)");
  }
  const std::vector<unsigned char> head = gunzip_prefix(compressed, kHeaderBytes, file);
  if (head.size() < kHeaderBytes)
    throw InputError(file, "the .spz data ends within its 16-byte header (" + std::to_string(head.size()) + " bytes)");
  Header header;
  std::memcpy(&header, head.data(), kHeaderBytes);
  if (header.magic != kSpzMagic) throw InputError(file, "not a .spz model (no \"NGSP\" magic after inflating)");
  if (header.version != 2 && header.version != 3)
    throw InputError(file, "unsupported .spz version " + std::to_string(header.version) + " (2 and 3 are read)");
  if (header.sh_degree > kMaxShDegree)
    throw InputError(file, ".spz SH degree " + std::to_string(header.sh_degree) + " (at most 3 is read)");
  if (header.flags & kFlagExtensions) throw InputError(file, "the .spz file has extensions, which are not read");
  if (header.fractional_bits > 24)
    throw InputError(file, ".spz fractional bits " + std::to_string(header.fractional_bits) + " (at most 24)");
  if (header.count > kMaxGaussiansInAFile)
    throw InputError(file, "the header declares " + std::to_string(header.count) + " Gaussians, more than the " +
                               std::to_string(kMaxGaussiansInAFile) + " a model file may hold");
  return header;
}

}  // namespace

void write_spz_file(const GaussianModel& source, const std::filesystem::path& file, const SpzWriteOptions& options) {
  source.check_consistent();
  if (options.sh1_bits < 1 || options.sh1_bits > 8 || options.sh_rest_bits < 1 || options.sh_rest_bits > 8)
    throw ArgumentError(".spz SH bits must be 1..8");
  GaussianModel model = source;
  turn_half_about_x(model);
  const std::size_t n = model.size();
  const std::size_t coefficients = std::size_t(model.sh_coefficients());
  const int fractional_bits = fractional_bits_for(model);

  std::vector<unsigned char> bytes(kHeaderBytes + n * record_bytes(model.sh_degree, 4));
  const Header header{kSpzMagic, kSpzWrittenVersion, std::uint32_t(n), std::uint8_t(model.sh_degree),
                      std::uint8_t(fractional_bits), 0, 0};
  std::memcpy(bytes.data(), &header, kHeaderBytes);
  unsigned char* means = bytes.data() + kHeaderBytes;
  unsigned char* alphas = means + kMeanBytes * n;
  unsigned char* colors = alphas + n;
  unsigned char* scales = colors + 3 * n;
  unsigned char* rotations = scales + 3 * n;
  unsigned char* sh = rotations + 4 * n;
  const float fixed_point_scale = float(1 << fractional_bits);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t a = 0; a < 3; ++a) {
      const auto fixed = std::int32_t(std::round(model.means[3 * i + a] * fixed_point_scale));
      for (int b = 0; b < 3; ++b) means[(3 * i + a) * 3 + b] = std::uint8_t((fixed >> (8 * b)) & 0xff);
      colors[3 * i + a] = to_byte(model.sh[i * coefficients * 3 + a] * (kColorScale * 255.0f) + 127.5f);
      scales[3 * i + a] = to_byte((model.log_scales[3 * i + a] + kLogScaleOffset) * kLogScaleSteps);
    }
    alphas[i] = to_byte(255.0f * model.opacity(i));
    const std::uint32_t rotation = pack_smallest_three(model.quat(i));
    std::memcpy(rotations + 4 * i, &rotation, 4);
    for (std::size_t k = 1; k < coefficients; ++k)
      for (std::size_t c = 0; c < 3; ++c)
        *sh++ = quantize_sh(model.sh[(i * coefficients + k) * 3 + c], k < 4 ? options.sh1_bits : options.sh_rest_bits);
  }
  const std::vector<unsigned char> compressed = gzip(bytes);
  write_stream_atomically(file, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(compressed.data()), static_cast<std::streamsize>(compressed.size()));
  });
}

GaussianModel read_spz_file(const std::filesystem::path& file) {
  const std::vector<unsigned char> compressed =
      read_file_bytes(file, std::numeric_limits<std::uint32_t>::max(), "a .spz model");
  const Header header = read_header(compressed, file);
  const std::size_t n = header.count;
  const std::size_t rotation_bytes = header.version >= 3 ? 4 : 3;
  const std::size_t expected = kHeaderBytes + n * record_bytes(header.sh_degree, rotation_bytes);
  const std::vector<unsigned char> bytes = gunzip(compressed, expected, file);
  if (bytes.size() != expected)
    throw InputError(file, "the .spz data holds " + std::to_string(bytes.size()) + " bytes; its header (" +
                               std::to_string(n) + " Gaussians, SH degree " + std::to_string(header.sh_degree) +
                               ") needs " + std::to_string(expected));

  GaussianModel model;
  model.sh_degree = header.sh_degree;
  model.resize(n);
  const std::size_t coefficients = std::size_t(model.sh_coefficients());
  const unsigned char* means = bytes.data() + kHeaderBytes;
  const unsigned char* alphas = means + kMeanBytes * n;
  const unsigned char* colors = alphas + n;
  const unsigned char* scales = colors + 3 * n;
  const unsigned char* rotations = scales + 3 * n;
  const unsigned char* sh = rotations + rotation_bytes * n;
  const float fixed_point_step = 1.0f / float(std::uint32_t(1) << header.fractional_bits);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t a = 0; a < 3; ++a) {
      const unsigned char* b = means + (3 * i + a) * 3;
      std::int32_t fixed = std::int32_t(b[0]) | std::int32_t(b[1]) << 8 | std::int32_t(b[2]) << 16;
      if (fixed & 0x800000) fixed -= 1 << 24;  // the 24-bit sign
      model.means[3 * i + a] = float(fixed) * fixed_point_step;
      model.sh[i * coefficients * 3 + a] = (colors[3 * i + a] / 255.0f - 0.5f) / kColorScale;
      model.log_scales[3 * i + a] = scales[3 * i + a] / kLogScaleSteps - kLogScaleOffset;
    }
    model.opacity_logits[i] = opacity_logit_from_byte(alphas[i]);
    Vec4<float> q;
    if (rotation_bytes == 4) {
      std::uint32_t packed;
      std::memcpy(&packed, rotations + 4 * i, 4);
      q = unpack_smallest_three(packed);
    } else {
      q = unpack_first_three(rotations + 3 * i);
    }
    for (int a = 0; a < 4; ++a) model.quats[4 * i + a] = q[a];
    for (std::size_t k = 1; k < coefficients; ++k)
      for (std::size_t c = 0; c < 3; ++c) model.sh[(i * coefficients + k) * 3 + c] = (float(*sh++) - 128.0f) / 128.0f;
  }
  turn_half_about_x(model);
  return model;
}

}  // namespace splat
