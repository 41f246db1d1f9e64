#pragma once
// Point clouds stored as PLY (nerfstudio's sparse_pc.ply, or any tool's points): the vertex
// element's x, y, z and, when present, red, green, blue. They start the Gaussians of a
// nerfstudio dataset as COLMAP's points3D do.
#include <filesystem>

#include "splat/data/dataset.hpp"

namespace splat {

// At most this many points: 16 × what COLMAP reconstructs of a large capture.
constexpr std::uint64_t kMaxPointCloudPoints = std::uint64_t(1) << 26;

// Reads `file` (ASCII or binary of either byte order). Positions may be of any scalar type;
// colours of an integer type are 0–255, of a float type 0–1; without colours the points are
// mid-grey. InputError naming the file when it is not a PLY, has no vertex element or no
// x/y/z, holds a non-finite position, is truncated, or declares more than the limit.
PointCloud read_point_cloud_ply(const std::filesystem::path& file);

}  // namespace splat
