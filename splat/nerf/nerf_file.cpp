#include "splat/nerf/nerf_file.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "splat/core/atomic_file.hpp"
#include "splat/core/json_file.hpp"
#include "splat/core/error.hpp"
#include "splat/core/file_bytes.hpp"

namespace splat {

namespace {

constexpr char kMagic[8] = {'S', 'P', 'L', 'A', 'T', 'N', 'R', 'F'};
constexpr char kNgpMagic[8] = {'S', 'P', 'L', 'A', 'T', 'N', 'G', 'P'};
constexpr std::uint64_t kMaxArray = std::uint64_t(1) << 32;

template <class T>
void write_array(std::ostream& out, std::span<const T> values) {
  const std::uint64_t n = values.size();
  out.write(reinterpret_cast<const char*>(&n), sizeof(n));
  out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(n * sizeof(T)));
}

template <class T>
std::vector<T> read_array(std::istream& in, const std::filesystem::path& file, const char* what,
                          std::size_t expected) {
  std::uint64_t n = 0;
  in.read(reinterpret_cast<char*>(&n), sizeof(n));
  if (!in) throw InputError(file, std::string("truncated before the ") + what);
  if (n != expected || n > kMaxArray)
    throw InputError(file, std::string(what) + ": " + std::to_string(n) + " values where the settings give " +
                               std::to_string(expected));
  std::vector<T> values(n);
  in.read(reinterpret_cast<char*>(values.data()), std::streamsize(n * sizeof(T)));
  if (!in) throw InputError(file, std::string("truncated in the ") + what);
  return values;
}

}  // namespace

nlohmann::json nerf_settings_json(const NerfSettings& s) { return settings_json(s); }

bool uses_hash_encoding(const NerfSettings& s) {
  return s.coarse.encoding == PositionEncoding::kHash || s.fine.encoding == PositionEncoding::kHash;
}

std::string nerf_file_extension(const NerfSettings& s) { return uses_hash_encoding(s) ? ".ngp" : ".nerf"; }

NerfSettings read_nerf_settings(const nlohmann::json& j, SettingsReading how) {
  // Older files lack render_sample_multiplier (they render with 1, the value before it) and
  // unbounded (false), or give the density threshold itself (occupancy_threshold) instead of
  // the optical thickness; every file adds the networks' parameter counts, which the reader
  // compares with the arrays.
  const bool threshold = j.is_object() && j.contains("occupancy_threshold");
  how.optional = {"render_sample_multiplier", "unbounded"};
  if (threshold) how.optional.push_back("occupancy_optical_thickness");
  how.ignored = {"occupancy_threshold", "coarse_parameters", "fine_parameters"};
  NerfSettings s;
  s.render_sample_multiplier = 1;
  read_settings(j, s, how);
  if (threshold)
    s.occupancy_optical_thickness =
        read_setting<float>(j.at("occupancy_threshold"), how.path + ".occupancy_threshold", {0, 1e6}) * s.coarse_step();
  validate(s, how.path);
  return s;
}

NerfSettings nerf_settings_from_json(const nlohmann::json& j) {
  return read_nerf_settings(j, {.path = "model", .unknown = "unknown NeRF setting", .every_key = true});
}

void write_nerf_to(std::ostream& out, const NerfModel& model) {
  out.write(uses_hash_encoding(model.settings) ? kNgpMagic : kMagic, sizeof(kMagic));
  const std::uint32_t version = kNerfFileVersion;
  out.write(reinterpret_cast<const char*>(&version), sizeof(version));
  nlohmann::json settings = nerf_settings_json(model.settings);
  settings["coarse_parameters"] = model.coarse.parameter_count();
  settings["fine_parameters"] = model.fine.parameter_count();
  const std::string text = settings.dump();
  const std::uint32_t length = std::uint32_t(text.size());
  out.write(reinterpret_cast<const char*>(&length), sizeof(length));
  out.write(text.data(), std::streamsize(text.size()));
  write_array<float>(out, model.coarse.parameters());
  write_array<float>(out, model.fine.parameters());
  write_array<float>(out, model.grid.values());
  write_array<std::uint8_t>(out, model.grid.occupancy());
}

NerfModel read_nerf_from(std::istream& in, const std::filesystem::path& file) {
  char magic[8] = {};
  in.read(magic, sizeof(magic));
  const bool ngp = in && std::memcmp(magic, kNgpMagic, sizeof(kNgpMagic)) == 0;
  if (!in || (!ngp && std::memcmp(magic, kMagic, sizeof(kMagic)) != 0))
    throw InputError(file, "not a splat NeRF model (missing the SPLATNRF or SPLATNGP header)");
  std::uint32_t version = 0, length = 0;
  in.read(reinterpret_cast<char*>(&version), sizeof(version));
  if (!in) throw InputError(file, "truncated header");
  if (version != kNerfFileVersion)
    throw InputError(file, "format version " + std::to_string(version) + ", this build reads version " +
                               std::to_string(kNerfFileVersion));
  in.read(reinterpret_cast<char*>(&length), sizeof(length));
  if (!in || length > (1u << 20)) throw InputError(file, "truncated or oversized settings header");
  std::string text(length, '\0');
  in.read(text.data(), std::streamsize(length));
  if (!in) throw InputError(file, "truncated settings header");
  NerfSettings settings;
  try {
    settings = nerf_settings_from_json(nlohmann::json::parse(text));
  } catch (const std::exception& e) {
    throw InputError(file, "bad settings header: " + json_error_text(e));
  }
  if (ngp != uses_hash_encoding(settings))
    throw InputError(file, ngp ? "the SPLATNGP header's networks have no hash encoding"
                               : "the SPLATNRF header's networks are hash-encoded (an NGP model is SPLATNGP)");
  NerfModel model = [&] {
    try {
      return NerfModel(settings, 0);
    } catch (const std::exception& e) {
      throw InputError(file, "bad settings header: " + json_error_text(e));
    }
  }();
  const auto coarse = read_array<float>(in, file, "coarse parameters", model.coarse.parameter_count());
  const auto fine = read_array<float>(in, file, "fine parameters", model.fine.parameter_count());
  for (const auto* values : {&coarse, &fine})
    for (float v : *values)
      if (!std::isfinite(v)) throw InputError(file, "a network parameter is not finite");
  std::copy(coarse.begin(), coarse.end(), model.coarse.parameters().begin());
  std::copy(fine.begin(), fine.end(), model.fine.parameters().begin());
  const auto values = read_array<float>(in, file, "occupancy values", model.grid.cell_count());
  const auto flags = read_array<std::uint8_t>(in, file, "occupancy flags", model.grid.cell_count());
  model.grid.restore(values, flags);
  return model;
}

void write_nerf(const NerfModel& model, const std::filesystem::path& file) {
  write_stream_atomically(file, [&](std::ostream& out) { write_nerf_to(out, model); });
}

NerfModel read_nerf(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "cannot open the file");
  NerfModel model = read_nerf_from(in, file);
  expect_end_of_file(in, file, "the model's occupancy grid");
  return model;
}

bool is_nerf_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  char magic[8] = {};
  in.read(magic, sizeof(magic));
  return in && (std::memcmp(magic, kMagic, sizeof(kMagic)) == 0 || std::memcmp(magic, kNgpMagic, sizeof(kNgpMagic)) == 0);
}

}  // namespace splat
