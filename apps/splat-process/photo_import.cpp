#include "apps/splat-process/photo_import.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include "splat/core/error.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/resample.hpp"

namespace fs = std::filesystem;

namespace splat::process {
namespace {

bool is_image_name(const fs::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension == ".jpg" || extension == ".jpeg" || extension == ".png";
}

}  // namespace

std::vector<fs::path> list_images(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw InputError(folder, "folder does not exist");
  if (!fs::is_directory(folder, ec)) throw InputError(folder, "not a folder of photos");
  std::vector<fs::path> images;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, ec))
    if (entry.is_regular_file() && is_image_name(entry.path())) images.push_back(entry.path());
  if (ec) throw InputError(folder, "cannot list the folder: " + ec.message());
  if (images.empty()) throw InputError(folder, "holds no images (.jpg, .jpeg or .png files)");
  std::sort(images.begin(), images.end());
  return images;
}

ImportedPhotos import_photos(const std::vector<fs::path>& photos, const fs::path& images_dir, int max_side) {
  ImportedPhotos imported;
  std::vector<ImageInfo> sizes;
  for (const fs::path& photo : photos) {
    const ImageInfo& info = sizes.emplace_back(read_image_stored_size(photo));
    if (std::max(info.width, info.height) > std::max(imported.largest_width, imported.largest_height)) {
      imported.largest_width = info.width;
      imported.largest_height = info.height;
    }
  }
  const int longest = std::max(imported.largest_width, imported.largest_height);
  if (max_side > 0 && longest > max_side) imported.scale = double(max_side) / double(longest);
  fs::create_directories(images_dir);
  std::set<std::string> names;
  for (std::size_t i = 0; i < photos.size(); ++i) {
    const fs::path& photo = photos[i];
    const std::string name = imported.scale < 1.0 ? photo.stem().string() + ".png" : photo.filename().string();
    if (!names.insert(name).second)
      throw InputError(photo, "another photo of the folder has the same name once downscaled (" + name + ")");
    if (imported.scale == 1.0) {
      fs::copy_file(photo, images_dir / name, fs::copy_options::overwrite_existing);
      continue;
    }
    // Decoded at the whole reduction below the scale (a JPEG at 1/2, 1/4 or 1/8 by libjpeg),
    // so a photo beyond the pixel limit loads, then averaged to the exact size.
    const ImageInfo& stored = sizes[i];
    const Image image = read_image_reduced(photo, std::max(1, int(std::floor(1.0 / imported.scale))));
    const int width = std::max(1, int(std::lround(stored.width * imported.scale)));
    const int height = std::max(1, int(std::lround(stored.height * imported.scale)));
    write_png(image.width == width && image.height == height ? image : resample_area(image, width, height),
              images_dir / name);
  }
  return imported;
}

}  // namespace splat::process
