// Point clouds from PLY (point_cloud_ply.hpp): nerfstudio's ASCII sparse_pc.ply, binary files
// of either byte order with other properties beside, no colours, and clear errors.
#include "splat/data/point_cloud_ply.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

fs::path corpus(const std::string& name) { return fs::path(SPLAT_SOURCE_DIR) / "fuzz" / "corpus" / "point_cloud" / name; }

TEST(PointCloudPly, ReadsNerfstudiosAsciiLayout) {
  const PointCloud cloud = read_point_cloud_ply(corpus("nerfstudio.ply"));
  ASSERT_EQ(cloud.size(), 3u);
  EXPECT_EQ(cloud.positions, (std::vector<float>{0.5f, -1, 2, 1e-3f, 4, -2.5f, 0, 0, 0}));
  EXPECT_EQ(cloud.colors[0], 1.0f);
  EXPECT_EQ(cloud.colors[1], 0.0f);
  EXPECT_FLOAT_EQ(cloud.colors[2], 17.0f / 255.0f);
}

TEST(PointCloudPly, ReadsBinaryOfEitherByteOrderAndWithoutColours) {
  for (const char* name : {"binary_le.ply", "binary_be.ply"}) {
    const PointCloud cloud = read_point_cloud_ply(corpus(name));
    ASSERT_EQ(cloud.size(), 2u) << name;
    EXPECT_EQ(cloud.positions, (std::vector<float>{1, 2, 3, -1.5f, 0.25f, 8})) << name;
    EXPECT_FLOAT_EQ(cloud.colors[3], 1.0f) << name;
    EXPECT_FLOAT_EQ(cloud.colors[4], 128.0f / 255.0f) << name;
    EXPECT_FLOAT_EQ(cloud.colors[0], 10.0f / 255.0f) << name;
  }
  const PointCloud grey = read_point_cloud_ply(corpus("grey.ply"));  // and a face element after
  ASSERT_EQ(grey.size(), 2u);
  EXPECT_EQ(grey.positions[5], 6.0f);
  for (const float c : grey.colors) EXPECT_EQ(c, 0.5f);
}

TEST(PointCloudPly, ClearErrors) {
  const fs::path dir = test::scratch_dir("point_cloud_ply_errors");
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"not a ply at all\n", ""},
      {head + "end_header\n1 2\n3 4\n", "the vertex element has no 'z' property"},
      {head + "property float z\nend_header\n1 2 3\n", "truncated: the header declares 2 points"},
      {head + "property float z\nend_header\n1 2 3\n4 nan 6\n", "point 1 has a non-finite position"},
      {head + "property float z\nend_header\n1 2 3\n4 five 6\n", "point 1: 'five' is not a number"},
      {head + "property float z\nend_header\n1 2 3\n4 5 6 7\n", "point 1: expected 3 values"},
      {"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n123456789012",
       "truncated: the header declares 1000 points"},
      {"ply\nformat ascii 1.0\nelement face 1\nproperty float x\nend_header\n1\n", "no 'vertex' element"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path file = dir / ("case_" + std::to_string(i) + ".ply");
    test::write_text(file, cases[i].first);
    try {
      read_point_cloud_ply(file);
      ADD_FAILURE() << "case " << i << " loaded";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(cases[i].second), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace splat
