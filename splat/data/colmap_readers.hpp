#pragma once
// Internal to the COLMAP reader: the binary (colmap_binary.cpp) and text (colmap_text.cpp)
// forms, and the checks both share (colmap_model.cpp), so the two forms accept and reject
// exactly the same models.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "splat/data/colmap_model.hpp"

namespace splat::colmap_detail {

std::vector<ColmapCamera> read_cameras_binary(const std::filesystem::path& file);
std::vector<ColmapImage> read_images_binary(const std::filesystem::path& file);
void read_points_binary(const std::filesystem::path& file, std::vector<float>& positions,
                        std::vector<float>& colors);

std::vector<ColmapCamera> read_cameras_text(const std::filesystem::path& file);
std::vector<ColmapImage> read_images_text(const std::filesystem::path& file);
void read_points_text(const std::filesystem::path& file, std::vector<float>& positions,
                      std::vector<float>& colors);

// Model id from its COLMAP name ("PINHOLE"), or -1 for a name COLMAP does not define.
int model_id_from_name(std::string_view name);

// The supported model for `model_id`; InputError naming `file` and the model otherwise.
// `where` locates the record in messages ("line 5", "camera 3").
ColmapCameraModel supported_model(const std::filesystem::path& file, const std::string& where,
                                  int model_id);
// Plausible size, finite positive focal lengths, finite parameters.
void check_camera(const std::filesystem::path& file, const std::string& where,
                  const ColmapCamera& camera);
// Finite pose, a quaternion that can be normalised, a non-empty name.
void check_image(const std::filesystem::path& file, const std::string& where,
                 const ColmapImage& image);
// A 3D point: finite position; colours are already 8-bit by construction.
void check_point(const std::filesystem::path& file, const std::string& where, const double xyz[3]);

}  // namespace splat::colmap_detail
