#pragma once
// The .splat format web viewers load (antimatter15's WebGL viewer, SuperSplat, PlayCanvas
// splat-transform): no header, 32 bytes per Gaussian, little-endian, in the PLY's world frame:
//
//   float32 x, y, z          the mean
//   float32 sx, sy, sz       the axes' scales, exp(log_scale)
//   uint8   r, g, b, a       r = 255·(0.5 + C0·f_dc_0) rounded and clamped to 0..255 (the
//                            colour of the DC band alone), a = 255·sigmoid(opacity) rounded
//   uint8   q0..q3           the unit quaternion (w, x, y, z), each 128 + 128·q rounded and
//                            clamped to 0..255
//
// The format has no higher SH bands: a model loses them (view-dependent colour) when written,
// and reads back at degree 0. docs/DESIGN.md §4.12 gives the losses.
#include <filesystem>

#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

constexpr std::size_t kSplatRecordBytes = 32;

// Written to a temporary name and renamed into place.
void write_splat_file(const GaussianModel& model, const std::filesystem::path& file);

// InputError naming the file when it is missing, empty, not a whole number of records, holds
// more than kMaxGaussiansInAFile, or has a non-finite mean, a scale that is not positive and
// finite, or a rotation of length zero. Opacity bytes 0 and 255 read as 0.5/255 and 254.5/255
// (the logit of 0 or 1 is infinite).
GaussianModel read_splat_file(const std::filesystem::path& file);

}  // namespace splat
