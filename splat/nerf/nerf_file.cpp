#include "splat/nerf/nerf_file.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "splat/core/atomic_file.hpp"
#include "splat/core/json_file.hpp"
#include "splat/core/error.hpp"
#include "splat/core/setting_value.hpp"
#include "splat/nerf/positional_encoding.hpp"

namespace splat {

namespace {

constexpr char kMagic[8] = {'S', 'P', 'L', 'A', 'T', 'N', 'R', 'F'};
constexpr std::uint64_t kMaxArray = std::uint64_t(1) << 32;

nlohmann::json mlp_json(const NerfMlpConfig& c) {
  return {{"position_frequencies", c.position_frequencies},
          {"direction_frequencies", c.direction_frequencies},
          {"depth", c.depth}, {"width", c.width}, {"skip_layer", c.skip_layer},
          {"color_width", c.color_width},
          {"density_activation", c.density_activation == DensityActivation::kRelu ? "relu" : "softplus"}};
}

// Throws ArgumentError naming the first key of `j` that is not in `known`.
void require_known_keys(const nlohmann::json& j, const std::string& where,
                        std::initializer_list<const char*> known) {
  if (!j.is_object()) throw ArgumentError(where + " must be a JSON object");
  for (const auto& item : j.items())
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return item.key() == k; }))
      throw ArgumentError("unknown NeRF setting \"" + where + "." + item.key() + "\"");
}

template <class T>
T setting(const nlohmann::json& j, const std::string& where, const char* key, const SettingRange& range) {
  const auto it = j.find(key);
  if (it == j.end()) throw ArgumentError("\"" + where + "." + key + "\" is missing");
  return read_setting<T>(*it, where + "." + key, range);
}

NerfMlpConfig mlp_from_json(const nlohmann::json& j, const std::string& where) {
  require_known_keys(j, where, {"position_frequencies", "direction_frequencies", "depth", "width",
                                "skip_layer", "color_width", "density_activation"});
  NerfMlpConfig c;
  const SettingRange frequencies{0, kMaxEncodingFrequencies};
  c.position_frequencies = setting<int>(j, where, "position_frequencies", frequencies);
  c.direction_frequencies = setting<int>(j, where, "direction_frequencies", frequencies);
  c.depth = setting<int>(j, where, "depth", {1, kMaxNerfDepth});
  c.width = setting<int>(j, where, "width", {1, kMaxNerfWidth});
  c.skip_layer = setting<int>(j, where, "skip_layer", {-1, kMaxNerfDepth - 1});
  c.color_width = setting<int>(j, where, "color_width", {1, kMaxNerfWidth});
  const auto activation = j.find("density_activation");
  if (activation == j.end() || !activation->is_string() ||
      (*activation != "relu" && *activation != "softplus"))
    throw ArgumentError("\"" + where + ".density_activation\" must be \"relu\" or \"softplus\"");
  c.density_activation = *activation == "relu" ? DensityActivation::kRelu : DensityActivation::kSoftplus;
  validate(c);
  return c;
}

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

nlohmann::json nerf_settings_json(const NerfSettings& s) {
  return {{"coarse", mlp_json(s.coarse)}, {"fine", mlp_json(s.fine)},
          {"coarse_samples", s.coarse_samples}, {"fine_samples", s.fine_samples},
          {"render_sample_multiplier", s.render_sample_multiplier},
          {"box_min", {s.box.lo.x, s.box.lo.y, s.box.lo.z}},
          {"box_max", {s.box.hi.x, s.box.hi.y, s.box.hi.z}}, {"unbounded", s.unbounded},
          {"near", s.near}, {"occupancy_resolution", s.occupancy_resolution},
          {"occupancy_optical_thickness", s.occupancy_optical_thickness}};
}

NerfSettings nerf_settings_from_json(const nlohmann::json& j) {
  const std::string where = "model";
  require_known_keys(j, where, {"coarse", "fine", "coarse_samples", "fine_samples", "render_sample_multiplier", "box_min", "box_max",
                                "unbounded", "near", "occupancy_resolution", "occupancy_optical_thickness",
                                "occupancy_threshold", "coarse_parameters", "fine_parameters"});
  NerfSettings s;
  if (!j.contains("coarse") || !j.contains("fine")) throw ArgumentError("\"model.coarse\" and \"model.fine\" are needed");
  s.coarse = mlp_from_json(j.at("coarse"), where + ".coarse");
  s.fine = mlp_from_json(j.at("fine"), where + ".fine");
  s.coarse_samples = setting<int>(j, where, "coarse_samples", {1, kMaxNerfSamplesPerRay});
  s.fine_samples = setting<int>(j, where, "fine_samples", {0, kMaxNerfSamplesPerRay});
  // Absent in files from before it: they render as they always did.
  s.render_sample_multiplier = 1;
  if (j.contains("render_sample_multiplier"))
    s.render_sample_multiplier = setting<int>(j, where, "render_sample_multiplier", {1, kMaxNerfRenderSampleMultiplier});
  const SettingRange coordinate{-kMaxNerfCoordinate, kMaxNerfCoordinate};
  for (const char* key : {"box_min", "box_max"}) {
    const auto it = j.find(key);
    if (it == j.end() || !it->is_array() || it->size() != 3)
      throw ArgumentError("\"" + where + "." + key + "\" needs 3 numbers");
    glm::vec3& corner = std::string(key) == "box_min" ? s.box.lo : s.box.hi;
    for (int a = 0; a < 3; ++a) corner[a] = read_setting<float>((*it)[std::size_t(a)], where + "." + key, coordinate);
  }
  if (!(s.box.lo.x < s.box.hi.x && s.box.lo.y < s.box.hi.y && s.box.lo.z < s.box.hi.z))
    throw ArgumentError("\"model.box_min\" must be below \"model.box_max\" on every axis");
  // Absent in files from before unbounded scenes.
  if (j.contains("unbounded")) s.unbounded = read_setting<bool>(j.at("unbounded"), where + ".unbounded", {});
  s.near = setting<float>(j, where, "near", {0, kMaxNerfCoordinate});
  s.occupancy_resolution = setting<int>(j, where, "occupancy_resolution", {1, kMaxOccupancyResolution});
  // Files and configs from before the optical thickness gave the density threshold itself.
  if (j.contains("occupancy_threshold"))
    s.occupancy_optical_thickness =
        setting<float>(j, where, "occupancy_threshold", {0, 1e6}) * s.coarse_step();
  else
    s.occupancy_optical_thickness = setting<float>(j, where, "occupancy_optical_thickness", {0, 1e6});
  return s;
}

void write_nerf_to(std::ostream& out, const NerfModel& model) {
  out.write(kMagic, sizeof(kMagic));
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
  if (!in || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    throw InputError(file, "not a splat NeRF model (missing the SPLATNRF header)");
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
  return read_nerf_from(in, file);
}

bool is_nerf_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  char magic[8] = {};
  in.read(magic, sizeof(magic));
  return in && std::memcmp(magic, kMagic, sizeof(kMagic)) == 0;
}

}  // namespace splat
