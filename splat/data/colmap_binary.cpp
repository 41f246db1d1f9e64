// COLMAP's binary model files (cameras.bin, images.bin, points3D.bin), little-endian, in the
// layout COLMAP's own writer uses (src/colmap/scene/reconstruction_io.cc).
#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "splat/data/colmap_readers.hpp"

namespace splat::colmap_detail {
namespace {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little,
              "the COLMAP binary reader assumes a little-endian host, as COLMAP's files are");

// Smallest record of each kind, to bound a count by the bytes left before reserving memory.
// camera: id, model, width, height, and at least SIMPLE_PINHOLE's 3 parameters.
constexpr std::uint64_t kMinCameraBytes = 4 + 4 + 8 + 8 + 3 * 8;
// image: id, quaternion, translation, camera id, a 1-character name and its terminator, and
// the 2D-point count.
constexpr std::uint64_t kMinImageBytes = 4 + 4 * 8 + 3 * 8 + 4 + 2 + 8;
constexpr std::uint64_t kPoint2DBytes = 8 + 8 + 8;  // x, y, point3D id
// point: id, xyz, rgb, error, track length (the track may be empty).
constexpr std::uint64_t kMinPointBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr std::uint64_t kTrackElementBytes = 4 + 4;  // image id, 2D point index
// Image names are paths; longer ones are garbage, not a file name.
constexpr std::size_t kMaxNameLength = 4096;

// Sequential reads from one file that never run past its end: every read and every count is
// checked against the bytes remaining, so truncated or garbage files fail with a message
// instead of a crash, a hang, or a huge allocation.
class BinaryFile {
 public:
  explicit BinaryFile(const fs::path& file) : file_(file), in_(file, std::ios::binary) {
    if (!in_) throw InputError(file, "cannot open the file for reading");
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    if (ec) throw InputError(file, "cannot determine the file size: " + ec.message());
    size_ = size;
  }

  template <class T>
  T read(const char* what) {
    T value;
    bytes(&value, sizeof(T), what);
    return value;
  }

  void skip(std::uint64_t count, const char* what) {
    need(count, what);
    in_.seekg(std::streamoff(count), std::ios::cur);
    position_ += count;
  }

  // A count of records each at least `min_bytes` long, which must all fit in the rest.
  std::uint64_t count(std::uint64_t min_bytes, const char* what) {
    const auto n = read<std::uint64_t>(what);
    if (n > remaining() / min_bytes)
      fail(std::string(what) + " " + std::to_string(n) + " does not fit in the " +
           std::to_string(remaining()) + " bytes left (truncated or corrupt file)");
    return n;
  }

  std::string null_terminated(const char* what) {
    std::string text;
    for (;;) {
      const char c = read<char>(what);
      if (c == '\0') return text;
      if (text.size() == kMaxNameLength)
        fail(std::string(what) + " longer than " + std::to_string(kMaxNameLength) +
             " characters (corrupt file)");
      text.push_back(c);
    }
  }

  void expect_end() {
    if (remaining() != 0)
      fail(std::to_string(remaining()) + " unexpected bytes after the last record");
  }

  [[noreturn]] void fail(const std::string& problem) const { throw InputError(file_, problem); }

 private:
  std::uint64_t remaining() const { return size_ - position_; }

  void need(std::uint64_t count, const char* what) const {
    if (count > remaining())
      fail(std::string("truncated at byte ") + std::to_string(position_) + " while reading " +
           what);
  }

  void bytes(void* out, std::size_t count, const char* what) {
    need(count, what);
    if (!in_.read(static_cast<char*>(out), std::streamsize(count)))
      fail(std::string("cannot read ") + what + " at byte " + std::to_string(position_));
    position_ += count;
  }

  fs::path file_;
  std::ifstream in_;
  std::uint64_t size_ = 0, position_ = 0;
};

std::string record(const char* kind, std::uint64_t number) {
  return std::string(kind) + " " + std::to_string(number);
}

// COLMAP writes ids as signed or unsigned 32-bit depending on the file; both are
// non-negative in valid models.
std::uint32_t camera_id_from(BinaryFile& in, const std::string& where) {
  const auto id = in.read<std::int32_t>("camera id");
  if (id < 0) in.fail(where + ": negative camera id " + std::to_string(id));
  return std::uint32_t(id);
}

int side_from(BinaryFile& in, const std::string& where, const char* what) {
  const auto side = in.read<std::uint64_t>(what);
  // check_camera reports implausible sizes; this only keeps the value representable.
  if (side > std::uint64_t(1) << 30)
    in.fail(where + ": implausible image " + what + " " + std::to_string(side));
  return int(side);
}

}  // namespace

std::vector<ColmapCamera> read_cameras_binary(const fs::path& file) {
  BinaryFile in(file);
  const std::uint64_t n = in.count(kMinCameraBytes, "camera count");
  std::vector<ColmapCamera> cameras;
  cameras.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    ColmapCamera camera;
    camera.id = camera_id_from(in, record("camera record", i));
    const std::string where = record("camera id", camera.id);
    camera.model = supported_model(file, where, in.read<std::int32_t>("camera model id"));
    camera.width = side_from(in, where, "width");
    camera.height = side_from(in, where, "height");
    camera.params.resize(std::size_t(colmap_parameter_count(camera.model)));
    for (double& p : camera.params) p = in.read<double>("camera parameter");
    check_camera(file, where, camera);
    cameras.push_back(std::move(camera));
  }
  in.expect_end();
  return cameras;
}

std::vector<ColmapImage> read_images_binary(const fs::path& file) {
  BinaryFile in(file);
  const std::uint64_t n = in.count(kMinImageBytes, "image count");
  std::vector<ColmapImage> images;
  images.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    ColmapImage image;
    image.id = in.read<std::uint32_t>("image id");
    const std::string where = record("image id", image.id);
    for (double& q : image.quaternion) q = in.read<double>("quaternion");
    for (double& t : image.translation) t = in.read<double>("translation");
    image.camera_id = in.read<std::uint32_t>("camera id");
    image.name = in.null_terminated("image name");
    // The 2D observations are not needed for splatting; skipping them is a seek, and
    // the count is checked against the bytes left like any other.
    const std::uint64_t points = in.count(kPoint2DBytes, "2D point count");
    in.skip(points * kPoint2DBytes, "2D points");
    check_image(file, where, image);
    images.push_back(std::move(image));
  }
  in.expect_end();
  return images;
}

void read_points_binary(const fs::path& file, std::vector<float>& positions,
                        std::vector<float>& colors) {
  BinaryFile in(file);
  const std::uint64_t n = in.count(kMinPointBytes, "point count");
  positions.reserve(n * 3);
  colors.reserve(n * 3);
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto id = in.read<std::uint64_t>("point id");
    double xyz[3];
    for (double& v : xyz) v = in.read<double>("point position");
    check_point(file, record("point id", id), xyz);
    for (double v : xyz) positions.push_back(float(v));
    for (int c = 0; c < 3; ++c)
      colors.push_back(float(in.read<std::uint8_t>("point colour")) / 255.0f);
    (void)in.read<double>("point error");
    const std::uint64_t track = in.count(kTrackElementBytes, "track length");
    in.skip(track * kTrackElementBytes, "track");
  }
  in.expect_end();
}

}  // namespace splat::colmap_detail
