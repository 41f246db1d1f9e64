#include "splat/gaussians/splat_file.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "splat/core/activations.hpp"
#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/core/file_bytes.hpp"
#include "splat/core/spherical_harmonics.hpp"
#include "splat/gaussians/byte_quantization.hpp"

namespace splat {
namespace {

static_assert(std::endian::native == std::endian::little, "the .splat reader and writer assume a little-endian host");

float read_float(const unsigned char* bytes) {
  float value;
  std::memcpy(&value, bytes, sizeof(float));
  return value;
}

void write_float(unsigned char* bytes, float value) { std::memcpy(bytes, &value, sizeof(float)); }

}  // namespace

void write_splat_file(const GaussianModel& model, const std::filesystem::path& file) {
  model.check_consistent();
  const std::size_t n = model.size();
  const std::size_t coefficients = static_cast<std::size_t>(model.sh_coefficients());
  std::vector<unsigned char> bytes(n * kSplatRecordBytes);
  for (std::size_t i = 0; i < n; ++i) {
    unsigned char* record = bytes.data() + i * kSplatRecordBytes;
    for (int a = 0; a < 3; ++a) {
      write_float(record + 4 * a, model.means[3 * i + a]);
      write_float(record + 12 + 4 * a, std::exp(model.log_scales[3 * i + a]));
    }
    for (int c = 0; c < 3; ++c)
      record[24 + c] = to_byte(255.0f * (0.5f + float(kShC0) * model.sh[i * coefficients * 3 + c]));
    record[27] = to_byte(255.0f * model.opacity(i));
    const Vec4<float> q = unit_quaternion(model.quat(i));
    for (int a = 0; a < 4; ++a) record[28 + a] = to_byte(128.0f + 128.0f * q[a]);
  }
  write_stream_atomically(file, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

GaussianModel read_splat_file(const std::filesystem::path& file) {
  const std::vector<unsigned char> bytes =
      read_file_bytes(file, kMaxGaussiansInAFile * kSplatRecordBytes, "a .splat model");
  if (bytes.empty()) throw InputError(file, "the .splat file is empty (no Gaussians)");
  if (bytes.size() % kSplatRecordBytes != 0)
    throw InputError(file, "the .splat file holds " + std::to_string(bytes.size()) +
                               " bytes, not a whole number of 32-byte Gaussians");
  const std::size_t n = bytes.size() / kSplatRecordBytes;
  GaussianModel model;
  model.sh_degree = 0;
  model.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* record = bytes.data() + i * kSplatRecordBytes;
    const std::string which = "Gaussian " + std::to_string(i);
    for (int a = 0; a < 3; ++a) {
      const float mean = read_float(record + 4 * a), scale = read_float(record + 12 + 4 * a);
      if (!std::isfinite(mean)) throw InputError(file, which + " has a mean that is not finite");
      if (!(scale > 0.0f) || !std::isfinite(scale))
        throw InputError(file, which + " has a scale that is not positive and finite");
      model.means[3 * i + a] = mean;
      model.log_scales[3 * i + a] = std::log(scale);
    }
    for (int c = 0; c < 3; ++c) model.sh[3 * i + c] = (record[24 + c] / 255.0f - 0.5f) / float(kShC0);
    model.opacity_logits[i] = opacity_logit_from_byte(record[27]);
    float q[4];
    for (int a = 0; a < 4; ++a) q[a] = (float(record[28 + a]) - 128.0f) / 128.0f;
    if (q[0] == 0 && q[1] == 0 && q[2] == 0 && q[3] == 0)
      throw InputError(file, which + " has a rotation of length zero");
    std::copy(q, q + 4, model.quats.begin() + std::ptrdiff_t(4 * i));
  }
  return model;
}

}  // namespace splat
