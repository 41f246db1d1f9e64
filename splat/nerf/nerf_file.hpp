#pragma once
// model.nerf and model.ngp: a trained NeRF in one binary file (little-endian).
//
//   bytes 0..7   magic "SPLATNRF", or "SPLATNGP" when the networks are hash-encoded
//                (Instant-NGP's method: the same layout, each network's parameter array
//                holding its hash tables after its layers)
//   u32          format version (kNerfFileVersion)
//   u32          length L of the settings JSON
//   L bytes      settings JSON (UTF-8): both networks' configs, sample counts, box, near,
//                occupancy resolution and threshold, and the parameter counts
//   u64 + f32[]  coarse network parameters (count, then values; nerf_mlp.hpp gives the order)
//   u64 + f32[]  fine network parameters
//   u64 + f32[]  occupancy grid values (resolution³, x fastest)
//   u64 + u8[]   occupancy grid flags
//
// A reader of another version, a truncated file, counts that disagree with the settings, or
// non-finite parameters: InputError naming the file and the problem.
#include <filesystem>
#include <iosfwd>
#include <nlohmann/json.hpp>

#include "splat/core/settings_table.hpp"
#include "splat/nerf/nerf_model.hpp"

namespace splat {

constexpr std::uint32_t kNerfFileVersion = 1;

// Written to a temporary name and renamed into place.
void write_nerf(const NerfModel& model, const std::filesystem::path& file);
NerfModel read_nerf(const std::filesystem::path& file);

// The same layout on an open stream (checkpoints embed a model); `file` names errors.
void write_nerf_to(std::ostream& out, const NerfModel& model);
NerfModel read_nerf_from(std::istream& in, const std::filesystem::path& file);

// The settings header as JSON, and back (ArgumentError or json exceptions on bad values).
nlohmann::json nerf_settings_json(const NerfSettings& settings);
NerfSettings nerf_settings_from_json(const nlohmann::json& json);
// The same, as a section of a config (`how` names it in errors): every key needed but those
// older files lack; validated.
NerfSettings read_nerf_settings(const nlohmann::json& json, SettingsReading how);

// Whether `file` starts with either magic (the viewer picks the reader by content).
bool is_nerf_file(const std::filesystem::path& file);

// Whether a network of the model is hash-encoded: then it is an NGP model (".ngp", magic
// SPLATNGP), otherwise ".nerf".
bool uses_hash_encoding(const NerfSettings& settings);
std::string nerf_file_extension(const NerfSettings& settings);

}  // namespace splat
