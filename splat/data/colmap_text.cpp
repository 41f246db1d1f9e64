// COLMAP's text model files (cameras.txt, images.txt, points3D.txt): one record per line,
// '#' comments, fields separated by spaces; images.txt gives each image two lines, the
// second holding its 2D points (often empty).
#include <charconv>
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/colmap_readers.hpp"

namespace splat::colmap_detail {
namespace {

namespace fs = std::filesystem;

constexpr int kImageFieldsBeforeName = 9;  // id, qw qx qy qz, tx ty tz, camera id
constexpr int kPointFields = 8;            // id, x y z, r g b, error (a track may follow)

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

template <class T>
bool parse(std::string_view token, T& value) {
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

// The file's lines, with line numbers for messages and '\r' of Windows line ends removed.
class TextFile {
 public:
  explicit TextFile(const fs::path& file) : file_(file), in_(file, std::ios::binary) {
    if (!in_) throw InputError(file, "cannot open the file for reading");
  }

  // The next line, comments included; false at the end of the file.
  bool next(std::string& line) {
    if (!std::getline(in_, line)) {
      if (in_.bad()) throw InputError(file_, "cannot read the file");
      return false;
    }
    ++line_number_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }

  // The next line that is neither blank nor a comment; false at the end of the file.
  bool next_record(std::string& line) {
    while (next(line))
      if (is_record(line)) return true;
    return false;
  }

  static bool is_record(const std::string& line) {
    const std::size_t first = line.find_first_not_of(" \t");
    return first != std::string::npos && line[first] != '#';
  }

  std::string where() const { return "line " + std::to_string(line_number_); }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(file_, where() + ": " + problem);
  }

  template <class T>
  T number(std::string_view token, const char* what) const {
    T value{};
    if (!parse(token, value))
      fail(std::string(what) + " must be a number, not \"" + std::string(token) + "\"");
    return value;
  }

  const fs::path& path() const { return file_; }

 private:
  fs::path file_;
  std::ifstream in_;
  int line_number_ = 0;
};

// A 2D-point line is a list of (x, y, point3D id) triples, possibly empty. Anything else
// after an image line is taken as the next image: hand-written files sometimes leave the
// 2D-point lines out, and skipping an image there would lose it silently.
bool is_points2d_line(std::string_view line) {
  const std::vector<std::string_view> tokens = split(line);
  if (tokens.size() % 3 != 0) return false;
  for (std::string_view token : tokens) {
    double value;
    if (!parse(token, value)) return false;
  }
  return true;
}

ColmapImage parse_image_line(const TextFile& in, const std::string& line) {
  const std::vector<std::string_view> tokens = split(line);
  if (int(tokens.size()) <= kImageFieldsBeforeName)
    in.fail("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
  ColmapImage image;
  image.id = in.number<std::uint32_t>(tokens[0], "image id");
  for (int k = 0; k < 4; ++k) image.quaternion[k] = in.number<double>(tokens[1 + k], "quaternion");
  for (int k = 0; k < 3; ++k) image.translation[k] = in.number<double>(tokens[5 + k], "translation");
  image.camera_id = in.number<std::uint32_t>(tokens[8], "camera id");
  // The name runs to the end of the line, so names with spaces survive.
  const std::size_t name_start = std::size_t(tokens[kImageFieldsBeforeName].data() - line.data());
  std::string_view name = std::string_view(line).substr(name_start);
  while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.remove_suffix(1);
  image.name = std::string(name);
  check_image(in.path(), in.where(), image);
  return image;
}

}  // namespace

std::vector<ColmapCamera> read_cameras_text(const fs::path& file) {
  TextFile in(file);
  std::vector<ColmapCamera> cameras;
  std::string line;
  while (in.next_record(line)) {
    const std::vector<std::string_view> tokens = split(line);
    if (tokens.size() < 4) in.fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    ColmapCamera camera;
    camera.id = in.number<std::uint32_t>(tokens[0], "camera id");
    const int model_id = model_id_from_name(tokens[1]);
    if (model_id < 0) in.fail("unknown camera model " + std::string(tokens[1]));
    camera.model = supported_model(file, in.where(), model_id);
    camera.width = in.number<int>(tokens[2], "width");
    camera.height = in.number<int>(tokens[3], "height");
    const std::size_t expected = std::size_t(colmap_parameter_count(camera.model));
    if (tokens.size() - 4 != expected)
      in.fail(colmap_model_name(model_id) + " takes " + std::to_string(expected) +
              " parameters, not " + std::to_string(tokens.size() - 4));
    for (std::size_t k = 0; k < expected; ++k)
      camera.params.push_back(in.number<double>(tokens[4 + k], "camera parameter"));
    check_camera(file, in.where(), camera);
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

std::vector<ColmapImage> read_images_text(const fs::path& file) {
  TextFile in(file);
  std::vector<ColmapImage> images;
  std::string line;
  bool have_line = in.next_record(line);
  while (have_line) {
    images.push_back(parse_image_line(in, line));
    // The line right after an image line holds its 2D points, blank or not.
    if (!in.next(line)) break;
    if (is_points2d_line(line))
      have_line = in.next_record(line);
    else
      have_line = TextFile::is_record(line) || in.next_record(line);
  }
  return images;
}

void read_points_text(const fs::path& file, std::vector<float>& positions,
                      std::vector<float>& colors) {
  TextFile in(file);
  std::string line;
  while (in.next_record(line)) {
    const std::vector<std::string_view> tokens = split(line);
    if (int(tokens.size()) < kPointFields)
      in.fail("expected POINT3D_ID X Y Z R G B ERROR TRACK[]");
    double xyz[3];
    for (int a = 0; a < 3; ++a) xyz[a] = in.number<double>(tokens[1 + a], "position");
    check_point(file, in.where(), xyz);
    for (double v : xyz) positions.push_back(float(v));
    for (int c = 0; c < 3; ++c) {
      const int value = in.number<int>(tokens[4 + c], "colour");
      if (value < 0 || value > 255) in.fail("colour must be 0 to 255, not " + std::to_string(value));
      colors.push_back(float(value) / 255.0f);
    }
  }
}

}  // namespace splat::colmap_detail
