#include "splat/raytrace/scene_spec.hpp"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"
#include "splat/core/json_file.hpp"

namespace splat::raytrace {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// No number in a spec may exceed this in magnitude (docs/DESIGN.md §4.8): positions, radii and
// intensities beyond it lose all precision in the ray tracer's floats (a camera radius of 1e19
// tripped an assertion inside Embree) or overflow them.
constexpr double kMaxSpecMagnitude = 1e6;

std::string magnitude_rule() { return "must be a number within ±1e6"; }

// Reads one JSON object, tracking the dotted path of each key ("cameras.radius") so every
// error names exactly what is wrong, and rejecting keys the spec does not define (a typo
// like "raduis" would otherwise silently fall back to a default).
class ObjectReader {
 public:
  ObjectReader(const fs::path& file, const json& object, std::string path)
      : file_(file), object_(object), path_(std::move(path)) {
    if (!object_.is_object()) fail(path_.empty() ? "the spec" : path_, "must be a JSON object");
  }

  void allow_only(std::initializer_list<const char*> keys) const {
    for (const auto& [key, value] : object_.items()) {
      bool known = false;
      for (const char* k : keys) known = known || key == k;
      if (!known) fail(name(key), "unknown key");
    }
  }
  bool has(const char* key) const { return object_.contains(key); }
  const json& get(const char* key) const {
    if (!object_.contains(key)) fail(name(key), "missing");
    return object_.at(key);
  }
  double number(const char* key) const {
    const json& v = get(key);
    if (!v.is_number()) fail(name(key), "must be a number");
    const double d = v.get<double>();
    if (!(std::abs(d) <= kMaxSpecMagnitude)) fail(name(key), magnitude_rule() + ", got " + v.dump());
    return d;
  }
  int integer(const char* key, int lo, int hi) const {
    const json& v = get(key);
    if (!v.is_number_integer()) fail(name(key), "must be an integer");
    const long long i = v.get<long long>();
    if (i < lo || i > hi)
      fail(name(key), "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                          std::to_string(i));
    return int(i);
  }
  std::string string(const char* key) const {
    const json& v = get(key);
    if (!v.is_string()) fail(name(key), "must be a string");
    return v.get<std::string>();
  }
  glm::vec3 vec3(const char* key) const { return vec3_of(get(key), name(key)); }
  glm::vec3 vec3_of(const json& v, const std::string& what) const {
    if (!v.is_array() || v.size() != 3) fail(what, "must be an array of 3 numbers");
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) {
      if (!v[i].is_number()) fail(what, "must be an array of 3 numbers");
      if (!(std::abs(v[i].get<double>()) <= kMaxSpecMagnitude))
        fail(what, magnitude_rule() + ", got " + v[i].dump());
      out[i] = v[i].get<float>();
    }
    return out;
  }
  std::string name(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  [[noreturn]] void fail(const std::string& what, const std::string& problem) const {
    throw InputError(file_, "\"" + what + "\": " + problem);
  }

 private:
  const fs::path& file_;
  const json& object_;
  std::string path_;
};

std::string number_text(double d) {
  std::ostringstream s;
  s << d;
  return s.str();
}

OrbitSpec read_orbit(const fs::path& file, const json& object) {
  const ObjectReader r(file, object, "cameras");
  r.allow_only({"rig", "target", "radius", "elevation_deg", "fov_deg", "width", "height", "train",
                "test"});
  if (r.string("rig") != "orbit") r.fail("cameras.rig", "only \"orbit\" is supported");
  OrbitSpec o;
  if (r.has("target")) o.target = r.vec3("target");
  o.radius = float(r.number("radius"));
  if (!(o.radius > 0)) r.fail("cameras.radius", "must be > 0, got " + number_text(o.radius));
  const json& band = r.get("elevation_deg");
  if (!band.is_array() || band.size() != 2 || !band[0].is_number() || !band[1].is_number())
    r.fail("cameras.elevation_deg", "must be [lo, hi] in degrees");
  o.elevation_lo_deg = band[0].get<float>();
  o.elevation_hi_deg = band[1].get<float>();
  // Beyond ±89° the camera would look straight along world up and its roll is undefined.
  for (float e : {o.elevation_lo_deg, o.elevation_hi_deg})
    if (!(e >= -89.0f && e <= 89.0f))
      r.fail("cameras.elevation_deg", "must lie within [-89, 89], got " + number_text(e));
  if (o.elevation_lo_deg > o.elevation_hi_deg) r.fail("cameras.elevation_deg", "needs lo <= hi");
  o.fov_x_deg = float(r.number("fov_deg"));
  if (!(o.fov_x_deg > 0 && o.fov_x_deg < 180))
    r.fail("cameras.fov_deg", "must be in (0, 180), got " + number_text(o.fov_x_deg));
  o.width = r.integer("width", 1, 4096);
  o.height = r.integer("height", 1, 4096);
  o.train = r.integer("train", 1, 100000);
  o.test = r.integer("test", 0, 100000);
  return o;
}

LightSpec read_light(const fs::path& file, const json& object, const std::string& path) {
  const ObjectReader r(file, object, path);
  LightSpec l;
  const std::string type = r.string("type");
  if (type == "directional") {
    r.allow_only({"type", "direction", "color", "intensity"});
    l.type = LightSpec::Type::directional;
    l.direction = r.vec3("direction");
    if (glm::length(l.direction) < 1e-12f) r.fail(r.name("direction"), "must not be zero");
    l.direction = glm::normalize(l.direction);
  } else if (type == "point") {
    r.allow_only({"type", "position", "color", "intensity"});
    l.type = LightSpec::Type::point;
    l.position = r.vec3("position");
  } else {
    r.fail(r.name("type"), "must be \"directional\" or \"point\", got \"" + type + "\"");
  }
  if (r.has("color")) l.color = r.vec3("color");
  if (glm::any(glm::lessThan(l.color, glm::vec3(0.0f)))) r.fail(r.name("color"), "must be >= 0");
  l.intensity = float(r.number("intensity"));
  if (!(l.intensity >= 0)) r.fail(r.name("intensity"), "must be >= 0");
  return l;
}

}  // namespace

SceneSpec load_scene_spec(const fs::path& spec_file) {
  const json doc = read_json_file(spec_file, "scene spec", JsonComments::kAllowed);
  const ObjectReader r(spec_file, doc, "");
  r.allow_only({"description", "gltf", "cameras", "lights", "ambient", "background",
                "samples_per_pixel", "seed"});
  SceneSpec spec;
  spec.spec_file = spec_file;
  if (r.has("description")) spec.description = r.string("description");
  const fs::path gltf = r.string("gltf");
  if (gltf.empty()) r.fail("gltf", "must not be empty");
  // The loader takes .glb as binary and anything else as text glTF: another extension would
  // be read as a format it does not name.
  if (const std::string ext = gltf.extension().string(); ext != ".gltf" && ext != ".glb" && ext != ".GLTF" && ext != ".GLB")
    r.fail("gltf", "must name a .gltf or .glb file, not '" + gltf.string() + "'");
  spec.gltf = gltf.is_absolute() ? gltf : spec_file.parent_path() / gltf;
  spec.cameras = read_orbit(spec_file, r.get("cameras"));
  if (r.has("lights")) {
    const json& lights = r.get("lights");
    if (!lights.is_array()) r.fail("lights", "must be an array");
    for (std::size_t i = 0; i < lights.size(); ++i)
      spec.lights.push_back(read_light(spec_file, lights[i], "lights[" + std::to_string(i) + "]"));
  }
  if (r.has("ambient")) {
    spec.ambient = r.vec3("ambient");
    if (glm::any(glm::lessThan(spec.ambient, glm::vec3(0.0f)))) r.fail("ambient", "must be >= 0");
  }
  if (r.has("background") && !r.get("background").is_null()) {
    const glm::vec3 bg = r.vec3("background");
    if (glm::any(glm::lessThan(bg, glm::vec3(0.0f))) || glm::any(glm::greaterThan(bg, glm::vec3(1.0f))))
      r.fail("background", "must be null or [r, g, b] in [0, 1]");
    spec.background = bg;
  }
  if (r.has("samples_per_pixel")) spec.samples_per_pixel = r.integer("samples_per_pixel", 1, 1024);
  if (r.has("seed")) spec.seed = unsigned(r.integer("seed", 0, 2147483647));
  return spec;
}

}  // namespace splat::raytrace
