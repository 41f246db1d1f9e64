#include "splat/nerf/nerf_file.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"

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

NerfMlpConfig mlp_from_json(const nlohmann::json& j) {
  NerfMlpConfig c;
  c.position_frequencies = j.at("position_frequencies").get<int>();
  c.direction_frequencies = j.at("direction_frequencies").get<int>();
  c.depth = j.at("depth").get<int>();
  c.width = j.at("width").get<int>();
  c.skip_layer = j.at("skip_layer").get<int>();
  c.color_width = j.at("color_width").get<int>();
  const std::string activation = j.at("density_activation").get<std::string>();
  if (activation != "relu" && activation != "softplus")
    throw ArgumentError("unknown density_activation '" + activation + "'");
  c.density_activation = activation == "relu" ? DensityActivation::kRelu : DensityActivation::kSoftplus;
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
          {"box_min", {s.box.lo.x, s.box.lo.y, s.box.lo.z}},
          {"box_max", {s.box.hi.x, s.box.hi.y, s.box.hi.z}}, {"unbounded", s.unbounded},
          {"near", s.near}, {"occupancy_resolution", s.occupancy_resolution},
          {"occupancy_optical_thickness", s.occupancy_optical_thickness}};
}

NerfSettings nerf_settings_from_json(const nlohmann::json& j) {
  NerfSettings s;
  s.coarse = mlp_from_json(j.at("coarse"));
  s.fine = mlp_from_json(j.at("fine"));
  s.coarse_samples = j.at("coarse_samples").get<int>();
  s.fine_samples = j.at("fine_samples").get<int>();
  const auto lo = j.at("box_min").get<std::vector<float>>(), hi = j.at("box_max").get<std::vector<float>>();
  if (lo.size() != 3 || hi.size() != 3) throw ArgumentError("box_min and box_max need 3 values");
  s.box = {glm::vec3(lo[0], lo[1], lo[2]), glm::vec3(hi[0], hi[1], hi[2])};
  s.unbounded = j.value("unbounded", false);  // absent in files from before unbounded scenes
  s.near = j.at("near").get<float>();
  s.occupancy_resolution = j.at("occupancy_resolution").get<int>();
  // Files and configs from before the optical thickness gave the density threshold itself.
  if (j.contains("occupancy_threshold"))
    s.occupancy_optical_thickness = j.at("occupancy_threshold").get<float>() * s.coarse_step();
  else
    s.occupancy_optical_thickness = j.at("occupancy_optical_thickness").get<float>();
  if (s.coarse_samples < 1 || s.coarse_samples > 4096 || s.fine_samples < 0 || s.fine_samples > 4096)
    throw ArgumentError("sample counts must be in 1..4096 (coarse) and 0..4096 (fine)");
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
    throw InputError(file, std::string("bad settings header: ") + e.what());
  }
  NerfModel model = [&] {
    try {
      return NerfModel(settings, 0);
    } catch (const std::exception& e) {
      throw InputError(file, std::string("bad settings header: ") + e.what());
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
  write_atomically(file, [&](const std::filesystem::path& temp) {
    std::ofstream out(temp, std::ios::binary);
    write_nerf_to(out, model);
    if (!out) throw InputError(file, "cannot write the file");
  });
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
