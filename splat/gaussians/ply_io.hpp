#pragma once
// Reading and writing the standard 3DGS PLY (the layout the official trainer writes and
// other splat viewers open):
//   x y z nx ny nz f_dc_0..2 f_rest_0..M-1 opacity scale_0..2 rot_0..3
// all `float`, f_rest channel-major (f_rest[c * (K-1) + (k-1)] for channel c, band index k),
// M = 3 * ((degree + 1)^2 - 1) so the SH degree is inferred from M.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

// One float property of the official layout and where it lives in the model: Gaussian i's
// value is (model.*array)[first + i * stride], in one of the model's parameter groups. The
// normals have no home (array == nullptr): nothing uses them, the official writer stores zeros.
struct PlyColumn {
  std::string name;
  std::vector<float> GaussianModel::*array = nullptr;
  std::size_t first = 0;
  std::size_t stride = 0;
};

// The properties of the official 3DGS PLY in file order for an SH degree. The writer (which
// must reproduce this order), the reader (which looks each one up by name) and splat-grad's
// gradient table use it, so none can disagree on the f_rest permutation.
std::vector<PlyColumn> official_ply_columns(int sh_degree);

// Reads binary little-endian, binary big-endian or ASCII PLY. Extra properties are ignored,
// properties may come in any order. Throws InputError naming the file on a missing file,
// wrong magic, truncated data, a vertex count the data cannot hold, a missing required
// property, a required property that is not float, an f_rest count that is no SH degree,
// or a NaN/Inf value (except an infinite opacity logit, which .spz decoders write for opacity
// bytes 0 and 255: it reads as our .spz reader reads those bytes). The normals (nx ny nz) are not required. Elements before "vertex" are
// skipped (in binary files only if all their properties are scalars), elements after it are
// ignored; list properties in the vertex element are an error. Sizes are checked against the
// file before anything is allocated, and the header must end within 64 KiB.
GaussianModel read_ply(const std::filesystem::path& file);

// Writes binary little-endian in the official layout (normals written as zeros), through a
// temporary file renamed into place, so a failure never leaves a half-written file.
void write_ply(const GaussianModel& model, const std::filesystem::path& file);

}  // namespace splat
