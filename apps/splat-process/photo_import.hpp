#pragma once
// The photographs a dataset starts from: found in a folder, and copied into the dataset's
// images/ at a size the trainer handles (downscaled when larger, never enlarged).
#include <filesystem>
#include <string>
#include <vector>

namespace splat::process {

// The images (.jpg, .jpeg, .png, any case) directly in `folder`, in name order. InputError
// naming the folder when it is missing, not a folder, or holds none.
std::vector<std::filesystem::path> list_images(const std::filesystem::path& folder);

struct ImportedPhotos {
  int largest_width = 0, largest_height = 0;  // of the photos as given
  double scale = 1.0;                          // applied to every photo (1: copied as they are)
};

// Copies `photos` into `images_dir`. When the longest side of the largest photo exceeds
// `max_side` (> 0), every photo is resampled (area average) by the one factor that brings it
// to `max_side` and written as PNG under its own stem; otherwise the files are copied
// byte for byte. Two photos with one stem are an InputError (their outputs would collide).
ImportedPhotos import_photos(const std::vector<std::filesystem::path>& photos, const std::filesystem::path& images_dir,
                             int max_side);

}  // namespace splat::process
