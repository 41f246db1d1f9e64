#include "splat/gaussians/model_file.hpp"

#include "splat/core/error.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/gaussians/splat_file.hpp"

namespace splat {

bool is_gaussian_model_extension(const std::string& extension) {
  return extension == ".ply" || extension == ".splat" || extension == ".spz";
}

GaussianModel read_gaussian_model(const std::filesystem::path& file) {
  const std::string extension = file.extension().string();
  if (extension == ".ply") return read_ply(file);
  if (extension == ".splat") return read_splat_file(file);
  if (extension == ".spz") return read_spz_file(file);
  throw InputError(file, "not a Gaussian model file (" + std::string(kGaussianModelExtensions) + " are read)");
}

void write_gaussian_model(const GaussianModel& model, const std::filesystem::path& file, const SpzWriteOptions& spz) {
  const std::string extension = file.extension().string();
  if (extension == ".ply") return write_ply(model, file);
  if (extension == ".splat") return write_splat_file(model, file);
  if (extension == ".spz") return write_spz_file(model, file, spz);
  throw ArgumentError(file.string() + ": not a Gaussian model format (" + std::string(kGaussianModelExtensions) +
                      " are written)");
}

}  // namespace splat
