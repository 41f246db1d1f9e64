#pragma once
// Writes small COLMAP models in both of COLMAP's forms for the tests: text exactly as
// COLMAP writes it, binary in its documented little-endian layout. Written here, from the
// format description, so the reader is checked against an independent writer.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "splat/data/colmap_model.hpp"

namespace splat::test {

struct TestPoint {
  double xyz[3];
  std::uint8_t rgb[3];
};

struct TestModel {
  std::vector<ColmapCamera> cameras;
  std::vector<ColmapImage> images;
  std::vector<TestPoint> points;
};

inline std::string exact(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", v);  // round-trips every double
  return text;
}

inline void write_colmap_text(const TestModel& m, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "cameras.txt", std::ios::binary);
    out << "# Camera list with one line of data per camera:\n"
        << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        << "# Number of cameras: " << m.cameras.size() << "\n";
    for (const ColmapCamera& c : m.cameras) {
      out << c.id << ' ' << colmap_model_name(int(c.model)) << ' ' << c.width << ' ' << c.height;
      for (double p : c.params) out << ' ' << exact(p);
      out << '\n';
    }
  }
  {
    std::ofstream out(dir / "images.txt", std::ios::binary);
    out << "# Image list with two lines of data per image:\n"
        << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
        << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
    for (std::size_t i = 0; i < m.images.size(); ++i) {
      const ColmapImage& im = m.images[i];
      out << im.id;
      for (double q : im.quaternion) out << ' ' << exact(q);
      for (double t : im.translation) out << ' ' << exact(t);
      out << ' ' << im.camera_id << ' ' << im.name << '\n';
      // Alternate empty and non-empty 2D point lines, as real models mix both.
      if (i % 2) out << "12.5 7.25 1 3.5 4.5 -1\n";
      else out << '\n';
    }
  }
  {
    std::ofstream out(dir / "points3D.txt", std::ios::binary);
    out << "# 3D point list with one line of data per point:\n"
        << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n";
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      const TestPoint& p = m.points[i];
      out << i + 1 << ' ' << exact(p.xyz[0]) << ' ' << exact(p.xyz[1]) << ' ' << exact(p.xyz[2])
          << ' ' << int(p.rgb[0]) << ' ' << int(p.rgb[1]) << ' ' << int(p.rgb[2]) << " 0.5";
      if (i % 2) out << " 1 0 2 1";
      out << '\n';
    }
  }
}

class BinaryOut {
 public:
  explicit BinaryOut(const std::filesystem::path& file) : out_(file, std::ios::binary) {}
  template <class T>
  void put(T v) { out_.write(reinterpret_cast<const char*>(&v), sizeof v); }
  void put_name(const std::string& s) { out_.write(s.c_str(), std::streamsize(s.size() + 1)); }

 private:
  std::ofstream out_;
};

inline void write_colmap_binary(const TestModel& m, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  {
    BinaryOut out(dir / "cameras.bin");
    out.put<std::uint64_t>(m.cameras.size());
    for (const ColmapCamera& c : m.cameras) {
      out.put<std::int32_t>(std::int32_t(c.id));
      out.put<std::int32_t>(std::int32_t(c.model));
      out.put<std::uint64_t>(std::uint64_t(c.width));
      out.put<std::uint64_t>(std::uint64_t(c.height));
      for (double p : c.params) out.put<double>(p);
    }
  }
  {
    BinaryOut out(dir / "images.bin");
    out.put<std::uint64_t>(m.images.size());
    for (std::size_t i = 0; i < m.images.size(); ++i) {
      const ColmapImage& im = m.images[i];
      out.put<std::uint32_t>(im.id);
      for (double q : im.quaternion) out.put<double>(q);
      for (double t : im.translation) out.put<double>(t);
      out.put<std::uint32_t>(im.camera_id);
      out.put_name(im.name);
      const std::uint64_t points2d = i % 2 ? 2 : 0;
      out.put<std::uint64_t>(points2d);
      for (std::uint64_t k = 0; k < points2d; ++k) {
        out.put<double>(12.5);
        out.put<double>(7.25);
        out.put<std::int64_t>(k == 0 ? 1 : -1);
      }
    }
  }
  {
    BinaryOut out(dir / "points3D.bin");
    out.put<std::uint64_t>(m.points.size());
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      const TestPoint& p = m.points[i];
      out.put<std::uint64_t>(i + 1);
      for (double v : p.xyz) out.put<double>(v);
      for (std::uint8_t c : p.rgb) out.put<std::uint8_t>(c);
      out.put<double>(0.5);
      const std::uint64_t track = i % 2 ? 2 : 0;
      out.put<std::uint64_t>(track);
      for (std::uint64_t k = 0; k < track; ++k) {
        out.put<std::int32_t>(std::int32_t(k + 1));
        out.put<std::int32_t>(std::int32_t(k));
      }
    }
  }
}

// A unit quaternion (w, x, y, z) for a rotation of `angle` about the axis (ax, ay, az).
inline std::array<double, 4> axis_angle_quaternion(double ax, double ay, double az, double angle) {
  const double n = std::sqrt(ax * ax + ay * ay + az * az), s = std::sin(angle / 2) / n;
  return {std::cos(angle / 2), ax * s, ay * s, az * s};
}

}  // namespace splat::test
