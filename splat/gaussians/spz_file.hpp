#pragma once
// The .spz format (Niantic's open compressed splat format, read by SuperSplat, PlayCanvas
// splat-transform and Niantic's viewers): a gzip stream of a 16-byte header and the
// Gaussians' quantised attributes, one array per attribute. The world is stored in the
// "right, up, back" convention; we turn models half about x on the way in and out
// (axis_flip.hpp), so a .spz opens upright where the PLY does. docs/DESIGN.md §4.12 gives
// every field and its quantisation:
//
//   header   u32 magic 0x5053474e ("NGSP"), u32 version (3 written; 2 and 3 read),
//            u32 count, u8 SH degree (0..3), u8 fractional bits, u8 flags, u8 reserved
//   means    3 × 24-bit signed fixed point, value · 2^fractional bits
//   alphas   u8 255·sigmoid(opacity)
//   colours  3 × u8 127.5 + 255·0.15·f_dc
//   scales   3 × u8 16·(log_scale + 10)
//   rotation version 3: u32 "smallest three" (index of the largest component of the unit
//            quaternion in 2 bits, the other three as sign + 9-bit magnitude over 1/√2);
//            version 2: 3 × u8 of (x, y, z) with w ≥ 0, 127.5 + 127.5·q
//   SH       per Gaussian the higher bands, coefficient-major and RGB innermost, each
//            u8 128 + 128·c rounded to a bucket of 2^(8 − bits) (6 bits by default)
#include <filesystem>

#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

constexpr std::uint32_t kSpzMagic = 0x5053474e;
constexpr std::uint32_t kSpzWrittenVersion = 3;

// Bits kept of each higher-band SH coefficient's byte (1..8): fewer bits compress better.
// Niantic's 5 and 4 cost trained real captures 4-5 dB (renders 34.9-36.0 dB from the PLY's,
// bench/HISTORY.md "Issue 41"); 6 and 6 keep them above 43 dB for a file about 30 % larger.
struct SpzWriteOptions {
  int sh1_bits = 6;
  int sh_rest_bits = 6;
};

// Written to a temporary name and renamed into place. Means are stored with the most
// fractional bits (at most 16) that fit the largest |coordinate| in 24 bits; ArgumentError
// when a coordinate is beyond ±2^23 or the options are out of range.
void write_spz_file(const GaussianModel& model, const std::filesystem::path& file,
                    const SpzWriteOptions& options = {});

// InputError naming the file when it is missing, not gzip, or corrupt; when the header's
// magic, version (2 or 3), SH degree (0..3), flags (extensions are not read) or count (at
// most kMaxGaussiansInAFile) is not one we read; or when the data is not exactly the size the
// header gives.
GaussianModel read_spz_file(const std::filesystem::path& file);

}  // namespace splat
