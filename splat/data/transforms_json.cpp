#include "splat/data/transforms_json.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"
#include "splat/core/json_file.hpp"
#include "splat/core/image.hpp"
#include "splat/data/image_io.hpp"
#include "splat/data/view_names.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// What NeRF-synthetic renders at when neither the JSON nor an image says otherwise.
constexpr int kDefaultImageSide = 800;
// A focal length of more than this many image sides is a field of view under 0.006 degrees.
constexpr double kMaxFocalPerImageSide = 1e4;
// transform_matrix must be rigid: stored rotations are accurate to float precision, and
// printed with six decimals at worst, far inside this.
constexpr double kRigidTolerance = 1e-3;
constexpr const char* kDefaultImageExtension = ".png";
constexpr double kPi = 3.14159265358979323846;

std::string format_number(double v) {
  std::ostringstream text;
  text << v;
  return text.str();
}

struct Size {
  int width = 0, height = 0;
};

struct RowMajor4x4 {
  double m[4][4];
};

json parse_file(const fs::path& file) { return read_json_file(file, "transforms file"); }

// A value looked up in a frame first, then at file level: per-frame intrinsics override the
// file's (nerfstudio writes them either way). `where` names it for messages.
struct Field {
  const json* value = nullptr;
  std::string where;
  explicit operator bool() const { return value != nullptr; }
};

class FrameReader {
 public:
  FrameReader(const fs::path& file, const json& root, const json& frame, std::size_t index)
      : file_(file), root_(root), frame_(frame), prefix_("frames[" + std::to_string(index) + "]") {}

  [[noreturn]] void fail(const std::string& problem) const { throw InputError(file_, problem); }
  [[noreturn]] void fail_here(const std::string& problem) const {
    fail(prefix_ + ": " + problem);
  }

  Field find(const char* key) const {
    const std::string quoted = std::string("\"") + key + "\"";
    if (auto it = frame_.find(key); it != frame_.end()) return {&*it, prefix_ + ": " + quoted};
    if (auto it = root_.find(key); it != root_.end()) return {&*it, quoted};
    return {};
  }

  double finite_number(const Field& field) const {
    if (!field.value->is_number()) fail(field.where + " must be a number");
    const double v = field.value->get<double>();
    if (!std::isfinite(v)) fail(field.where + " must be finite");
    return v;
  }

  int image_side(const Field& field) const {
    const double v = finite_number(field);
    if (v != std::floor(v) || v < 1 || v > kMaxImageSide)
      fail(field.where + " must be a whole number of pixels from 1 to " +
           std::to_string(kMaxImageSide) + ", not " + field.value->dump());
    return int(v);
  }

  void check_focal(double focal, const Size& size, const std::string& what) const {
    const double limit = kMaxFocalPerImageSide * std::max(size.width, size.height);
    if (!(focal > 0) || focal > limit)
      fail(what + " gives an implausible focal length of " + format_number(focal) +
           " pixels for a " + std::to_string(size.width) + " x " + std::to_string(size.height) +
           " image");
  }

  const std::string& file_path() const {
    auto it = frame_.find("file_path");
    if (it == frame_.end()) fail_here("missing \"file_path\"");
    if (!it->is_string() || it->get_ref<const std::string&>().empty())
      fail_here("\"file_path\" must be a non-empty string");
    return it->get_ref<const std::string&>();
  }

  // Row-major camera-to-world as written in the file.
  RowMajor4x4 transform_matrix() const {
    auto it = frame_.find("transform_matrix");
    if (it == frame_.end()) fail_here("missing \"transform_matrix\"");
    const std::string shape_problem = "\"transform_matrix\" must be a 4x4 array of numbers";
    if (!it->is_array() || it->size() != 4) fail_here(shape_problem);
    std::array<std::array<double, 4>, 4> m{};
    for (std::size_t r = 0; r < 4; ++r) {
      const json& row = (*it)[r];
      if (!row.is_array() || row.size() != 4) fail_here(shape_problem);
      for (std::size_t c = 0; c < 4; ++c) {
        if (!row[c].is_number()) fail_here(shape_problem);
        m[r][c] = row[c].get<double>();
        if (!std::isfinite(m[r][c])) fail_here("\"transform_matrix\" has a non-finite value");
      }
    }
    check_rigid(m);
    RowMajor4x4 out{};
    for (std::size_t r = 0; r < 4; ++r)
      for (std::size_t c = 0; c < 4; ++c) out.m[r][c] = m[r][c];
    return out;
  }

 private:
  // The conversion to the internal camera assumes a rotation and a translation; a scaled,
  // sheared, mirrored or projective matrix would give a camera that silently renders wrong.
  void check_rigid(const std::array<std::array<double, 4>, 4>& m) const {
    double worst = 0;
    for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(m[3][c] - (c == 3 ? 1 : 0)));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double dot = 0;  // (Rᵀ R)_ij over columns i and j
        for (int k = 0; k < 3; ++k) dot += m[k][i] * m[k][j];
        worst = std::max(worst, std::abs(dot - (i == j ? 1 : 0)));
      }
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (worst > kRigidTolerance || det < 0)
      fail_here("\"transform_matrix\" is not a rigid camera-to-world transform (rotation and "
                "translation, last row 0 0 0 1)");
  }

  const fs::path& file_;
  const json& root_;
  const json& frame_;
  std::string prefix_;
};

// "w"/"h" when given, else what `fallback` finds (the first image, or the default).
Size native_size(const FrameReader& reader, const std::function<Size()>& fallback) {
  const Field w = reader.find("w"), h = reader.find("h");
  if (w && h) {
    const Size size{reader.image_side(w), reader.image_side(h)};
    if (const std::string problem = camera_size_problem(size.width, size.height); !problem.empty())
      reader.fail(w.where + " x " + h.where + ": " + problem);
    return size;
  }
  if (w) reader.fail(w.where + " is given without \"h\"");
  if (h) reader.fail(h.where + " is given without \"w\"");
  return fallback();
}

// Focal lengths and principal point in pixels at the native size. fl_x, being exact, wins
// over camera_angle_x when a file has both.
void read_intrinsics(const FrameReader& reader, const Size& size, Camera& cam) {
  if (const Field fl_x = reader.find("fl_x")) {
    const auto focal = [&](const Field& field) {
      const double f = reader.finite_number(field);
      reader.check_focal(f, size, field.where);
      return float(f);
    };
    cam.fx = focal(fl_x);
    const Field fl_y = reader.find("fl_y");
    cam.fy = fl_y ? focal(fl_y) : cam.fx;
  } else if (const Field angle_x = reader.find("camera_angle_x")) {
    const auto focal_from_angle = [&](const Field& angle, int side) {
      const double a = reader.finite_number(angle);
      if (!(a > 0 && a < kPi))
        reader.fail(angle.where + " must be a field of view in radians between 0 and pi");
      const double focal = 0.5 * side / std::tan(0.5 * a);
      reader.check_focal(focal, size, angle.where);
      return float(focal);
    };
    cam.fx = focal_from_angle(angle_x, size.width);
    const Field angle_y = reader.find("camera_angle_y");
    cam.fy = angle_y ? focal_from_angle(angle_y, size.height) : cam.fx;
  } else {
    reader.fail_here("no intrinsics: neither \"camera_angle_x\" nor \"fl_x\" is given");
  }
  // Pixel centres sit at i + 0.5 (camera.hpp), so the image centre is exactly size / 2.
  const Field cx = reader.find("cx"), cy = reader.find("cy");
  cam.cx = cx ? float(reader.finite_number(cx)) : 0.5f * float(size.width);
  cam.cy = cy ? float(reader.finite_number(cy)) : 0.5f * float(size.height);
}

// nerfstudio's camera models that are a pinhole with COLMAP's radial-tangential distortion;
// the fisheye and panoramic ones are not.
void read_distortion(const FrameReader& reader, LensDistortion& distortion) {
  std::string model = "OPENCV";  // nerfstudio's default
  if (const Field field = reader.find("camera_model")) {
    if (!field.value->is_string()) reader.fail(field.where + " must be a string");
    model = field.value->get<std::string>();
  }
  const bool pinhole = model == "PINHOLE" || model == "SIMPLE_PINHOLE";
  if (!pinhole && model != "OPENCV")
    reader.fail(reader.find("camera_model").where + " is " + model +
                ", which is not supported: PINHOLE, SIMPLE_PINHOLE and OPENCV are (undistort fisheye "
                "or panoramic images first, e.g. with COLMAP's image_undistorter)");
  const auto coefficient = [&](const char* key) {
    const Field field = reader.find(key);
    return field ? reader.finite_number(field) : 0.0;
  };
  distortion = {coefficient("k1"), coefficient("k2"), coefficient("p1"), coefficient("p2")};
  for (const char* unsupported : {"k3", "k4"})
    if (coefficient(unsupported) != 0)
      reader.fail_here(std::string("\"") + unsupported +
                       "\" is not 0: OPENCV's k1, k2, p1, p2 are supported, higher radial terms are not");
  if (pinhole && !distortion.is_identity())
    reader.fail_here("camera model " + model + " has no lens distortion, but k1, k2, p1 or p2 is not 0");
}

fs::path resolve_image_path(const fs::path& json_file, const std::string& file_path) {
  fs::path path = (json_file.parent_path() / file_path).lexically_normal();
  if (!fs::path(file_path).has_extension()) path += kDefaultImageExtension;
  return path;
}

void check_options(const fs::path& file, const TransformsOptions& options) {
  const bool neither = options.width == 0 && options.height == 0;
  const bool both = options.width > 0 && options.height > 0 &&
                    image_size_problem(options.width, options.height).empty();
  // Deriving one side from the other would need each frame's aspect ratio; asking for both
  // keeps the output size what the caller wrote.
  if (!neither && !both)
    throw ArgumentError(file.string() + ": output size must give both width and height (1 to " +
                        std::to_string(kMaxImageSide) + " a side, at most " + std::to_string(kMaxImagePixels) +
                        " pixels) or neither, not " +
                        std::to_string(options.width) + " x " + std::to_string(options.height));
}

}  // namespace

std::vector<CameraFrame> load_transforms(const std::filesystem::path& file,
                                         const TransformsOptions& options) {
  check_options(file, options);
  const json root = parse_file(file);
  if (!root.is_object()) throw InputError(file, "expected a JSON object at the top level");
  const auto frames_it = root.find("frames");
  if (frames_it == root.end()) throw InputError(file, "missing \"frames\"");
  if (!frames_it->is_array()) throw InputError(file, "\"frames\" must be an array");
  if (frames_it->empty()) throw InputError(file, "\"frames\" is empty");

  // The first frame's image decides the size of frames without "w"/"h"; read its header once.
  fs::path first_image;
  std::optional<Size> first_image_size;
  const auto size_from_first_image = [&]() -> Size {
    if (!first_image_size) {
      std::error_code ec;
      if (fs::exists(first_image, ec)) {
        try {
          const ImageInfo info = read_image_stored_size(first_image);
          first_image_size = Size{info.width, info.height};
        } catch (const InputError& e) {
          throw InputError(file, std::string("cannot take the image size from the first frame: ") +
                                     e.what());
        }
      } else {
        first_image_size = Size{kDefaultImageSide, kDefaultImageSide};
      }
    }
    return *first_image_size;
  };

  std::vector<CameraFrame> result;
  result.reserve(frames_it->size());
  std::vector<fs::path> file_paths;
  for (std::size_t i = 0; i < frames_it->size(); ++i) {
    const json& frame = (*frames_it)[i];
    if (!frame.is_object())
      throw InputError(file, "frames[" + std::to_string(i) + "] must be a JSON object");
    const FrameReader reader(file, root, frame, i);

    CameraFrame out;
    const std::string& file_path = reader.file_path();
    out.name = fs::path(file_path).stem().string();
    if (out.name.empty()) reader.fail_here("\"file_path\" has no file name: " + file_path);
    file_paths.push_back(file_path);
    out.image_path = resolve_image_path(file, file_path);
    if (i == 0) first_image = out.image_path;

    const RowMajor4x4 camera_to_world_gl = reader.transform_matrix();
    const Size size = native_size(reader, size_from_first_image);
    Camera intrinsics;
    read_intrinsics(reader, size, intrinsics);
    out.camera = camera_from_blender(camera_to_world_gl.m, intrinsics.fx, intrinsics.fy, intrinsics.cx,
                                     intrinsics.cy, size.width, size.height);
    read_distortion(reader, out.distortion);
    if (const auto mask = frame.find("mask_path"); mask != frame.end()) {
      if (!mask->is_string() || mask->get_ref<const std::string&>().empty())
        reader.fail_here("\"mask_path\" must be a non-empty string");
      out.mask_path = (file.parent_path() / mask->get_ref<const std::string&>()).lexically_normal();
    }
    if (options.width > 0) out.camera = out.camera.resized(options.width, options.height);
    result.push_back(std::move(out));
  }
  const std::vector<std::string> names = view_names(file_paths, file);
  for (std::size_t i = 0; i < result.size(); ++i) result[i].name = names[i];
  return result;
}

}  // namespace splat
