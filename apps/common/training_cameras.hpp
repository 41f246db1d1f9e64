#pragma once
// The cameras splat-render's fly-throughs and the viewer follow when given no --cameras.
#include <filesystem>
#include <optional>

namespace splat::cli {

// The training views' cameras file a splat-train run left in `folder` (training_cameras_in),
// with a line on stdout saying it is used, so the user knows where the views came from.
std::optional<std::filesystem::path> announced_training_cameras(const std::filesystem::path& folder);

}  // namespace splat::cli
