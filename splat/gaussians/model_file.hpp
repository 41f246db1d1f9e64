#pragma once
// A Gaussian model file in any format we read or write, chosen by its extension: the 3DGS
// PLY (ply_io.hpp, lossless), .splat (splat_file.hpp) and .spz (spz_file.hpp), the web
// formats. The programs go through these, so each opens every format.
#include <filesystem>
#include <string>

#include "splat/gaussians/gaussian_model.hpp"
#include "splat/gaussians/spz_file.hpp"

namespace splat {

// Whether the extension (".ply", ".splat", ".spz"; lower case) names a Gaussian model format.
bool is_gaussian_model_extension(const std::string& extension);

// "... .ply, .splat or .spz", for messages.
constexpr const char* kGaussianModelExtensions = ".ply, .splat and .spz";

// Reads `file` by its extension. InputError naming the file for any other extension, and
// each reader's errors.
GaussianModel read_gaussian_model(const std::filesystem::path& file);

// Writes `model` to `file` in the format its extension names (atomically). ArgumentError for
// an extension that is no model format. `spz` applies to .spz only.
void write_gaussian_model(const GaussianModel& model, const std::filesystem::path& file,
                          const SpzWriteOptions& spz = {});

}  // namespace splat
