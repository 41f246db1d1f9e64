#pragma once
// A view's name names its outputs (splat-render's <name>.png, splat-train's test/<name>.png,
// the frames of the cameras files): every view of one file needs its own.
#include <filesystem>
#include <string>
#include <vector>

namespace splat {

// The names of the views whose images are at `image_paths` (as the file gives them, relative
// to its image folder): each image's stem, or, for images whose stems are alike (a rig's
// cam1/0001.jpg and cam2/0001.jpg), the path without its extension with '_' for '/'
// (cam1_0001). InputError naming `file` when two views still share a name, as when the same
// image is listed twice.
std::vector<std::string> view_names(const std::vector<std::filesystem::path>& image_paths,
                                    const std::filesystem::path& file);

}  // namespace splat
