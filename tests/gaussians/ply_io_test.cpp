#include "splat/gaussians/ply_io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "splat/core/error.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

// The hand-made binary files below are encoded on the host; flipping bytes for big-endian
// assumes a little-endian host, which is every machine this project targets.
static_assert(std::endian::native == std::endian::little);

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// ---- Building PLY files by hand ---------------------------------------------------------

struct Prop {
  std::string type;
  std::string name;
};
using Rows = std::vector<std::vector<double>>;  // [vertex][property]

// The official layout's property names for an SH degree, all float, in file order.
std::vector<Prop> official_props(int degree) {
  std::vector<Prop> props;
  for (const char* n : {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"})
    props.push_back({"float", n});
  const int rest = 3 * (sh_coefficient_count(degree) - 1);
  for (int j = 0; j < rest; ++j) props.push_back({"float", "f_rest_" + std::to_string(j)});
  for (const char* n : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2",
                        "rot_3"})
    props.push_back({"float", n});
  return props;
}

// Distinct values, exact in every type used here, so reads can be compared with ==.
Rows distinct_rows(const std::vector<Prop>& props, int count) {
  Rows rows(count);
  for (int i = 0; i < count; ++i)
    for (std::size_t j = 0; j < props.size(); ++j)
      rows[i].push_back(props[j].type == "float" || props[j].type == "double"
                            ? (i + 1) * 100.0 + double(j) + 0.25
                            : double((i * 7 + j) % 100));
  return rows;
}

std::string element_header(const std::string& name, std::size_t count,
                           const std::vector<Prop>& props) {
  std::string text = "element " + name + " " + std::to_string(count) + "\n";
  for (const Prop& p : props) text += "property " + p.type + " " + p.name + "\n";
  return text;
}

template <typename T>
void append_binary(std::string& out, T value, bool big_endian) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (big_endian) std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

std::string binary_rows(const std::vector<Prop>& props, const Rows& rows, bool big_endian) {
  std::string out;
  for (const std::vector<double>& row : rows) {
    for (std::size_t j = 0; j < props.size(); ++j) {
      const std::string& t = props[j].type;
      const double v = row[j];
      if (t == "float") append_binary(out, float(v), big_endian);
      else if (t == "double") append_binary(out, v, big_endian);
      else if (t == "uchar") append_binary(out, std::uint8_t(v), big_endian);
      else if (t == "char") append_binary(out, std::int8_t(v), big_endian);
      else if (t == "short" || t == "int16") append_binary(out, std::int16_t(v), big_endian);
      else if (t == "ushort") append_binary(out, std::uint16_t(v), big_endian);
      else if (t == "int") append_binary(out, std::int32_t(v), big_endian);
      else if (t == "uint32") append_binary(out, std::uint32_t(v), big_endian);
      else ADD_FAILURE() << "test encoder lacks type " << t;
    }
  }
  return out;
}

std::string ascii_rows(const std::vector<Prop>& props, const Rows& rows) {
  std::string out;
  for (const std::vector<double>& row : rows) {
    for (std::size_t j = 0; j < props.size(); ++j) {
      char buf[64];
      const bool is_float = props[j].type == "float" || props[j].type == "double";
      const auto result = is_float ? std::to_chars(buf, buf + sizeof buf, row[j])
                                   : std::to_chars(buf, buf + sizeof buf, std::int64_t(row[j]));
      out.append(buf, result.ptr);
      out += j + 1 < props.size() ? " " : "\n";
    }
  }
  return out;
}

// A one-element binary little-endian file: the usual shape of the bad-input cases.
std::string simple_ply(const std::vector<Prop>& props, const Rows& rows) {
  return "ply\nformat binary_little_endian 1.0\n" + element_header("vertex", rows.size(), props) +
         "end_header\n" + binary_rows(props, rows, false);
}

// ---- Checking ---------------------------------------------------------------------------

double value_of(const std::vector<Prop>& props, const std::vector<double>& row,
                const std::string& name) {
  for (std::size_t j = 0; j < props.size(); ++j)
    if (props[j].name == name) return row[j];
  ADD_FAILURE() << "no property " << name;
  return 0;
}

// Compares a model with the rows it was read from, using the layout rule written out
// independently of the library: sh[(i*K + k)*3 + c], f_rest index c*(K-1) + (k-1).
void expect_model_matches(const GaussianModel& m, const std::vector<Prop>& props,
                          const Rows& rows) {
  ASSERT_EQ(m.size(), rows.size());
  const int K = m.sh_coefficients();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    auto v = [&](const std::string& name) { return float(value_of(props, rows[i], name)); };
    const std::string axes = "xyz";
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(m.means[i * 3 + a], v(std::string(1, axes[a])));
      EXPECT_EQ(m.log_scales[i * 3 + a], v("scale_" + std::to_string(a)));
      EXPECT_EQ(m.sh[(i * K + 0) * 3 + a], v("f_dc_" + std::to_string(a)));
      for (int k = 1; k < K; ++k)
        EXPECT_EQ(m.sh[(i * K + k) * 3 + a], v("f_rest_" + std::to_string(a * (K - 1) + k - 1)))
            << "vertex " << i << " channel " << a << " coefficient " << k;
    }
    for (int a = 0; a < 4; ++a) EXPECT_EQ(m.quats[i * 4 + a], v("rot_" + std::to_string(a)));
    EXPECT_EQ(m.opacity_logits[i], v("opacity"));
  }
}

// read_ply must throw InputError whose message names the file and every word in `words`.
void expect_read_error(const fs::path& file, const std::vector<std::string>& words) {
  try {
    read_ply(file);
    ADD_FAILURE() << "read_ply accepted " << file;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    for (const std::string& w : words)
      EXPECT_NE(what.find(w), std::string::npos) << "'" << w << "' missing from: " << what;
  }
}

bool bitwise_equal(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

fs::path conformance_ply() { return test::conformance_dir() / "lego_subset50k.ply"; }

// ---- Round trips and the official layout ------------------------------------------------

TEST(PlyIo, RoundTripIsBitExactForEveryDegree) {
  const fs::path dir = test::scratch_dir("ply_round_trip");
  for (int degree = 0; degree <= kMaxShDegree; ++degree) {
    SCOPED_TRACE("degree " + std::to_string(degree));
    const GaussianModel original = test::random_model(257, degree, 11u + degree);
    const fs::path file = dir / ("model" + std::to_string(degree) + ".ply");
    write_ply(original, file);
    const GaussianModel back = read_ply(file);
    EXPECT_EQ(back.sh_degree, degree);
    EXPECT_EQ(back.size(), original.size());
    EXPECT_TRUE(bitwise_equal(back.means, original.means));
    EXPECT_TRUE(bitwise_equal(back.log_scales, original.log_scales));
    EXPECT_TRUE(bitwise_equal(back.quats, original.quats));
    EXPECT_TRUE(bitwise_equal(back.opacity_logits, original.opacity_logits));
    EXPECT_TRUE(bitwise_equal(back.sh, original.sh));
  }
}

TEST(PlyIo, WritesOfficialHeaderAndChannelMajorRest) {
  GaussianModel m;
  m.sh_degree = 1;
  m.resize(1);
  m.means = {1, 2, 3};
  m.log_scales = {4, 5, 6};
  m.quats = {7, 8, 9, 10};
  m.opacity_logits = {11};
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) m.sh[k * 3 + c] = float(100 + 10 * k + c);
  const fs::path file = test::scratch_dir("ply_layout") / "one.ply";
  write_ply(m, file);

  std::string expected_header = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n";
  for (const Prop& p : official_props(1)) expected_header += "property float " + p.name + "\n";
  expected_header += "end_header\n";
  const std::string bytes = read_bytes(file);
  ASSERT_EQ(bytes.size(), expected_header.size() + 26 * sizeof(float));
  EXPECT_EQ(bytes.substr(0, expected_header.size()), expected_header);

  std::vector<float> values(26);
  std::memcpy(values.data(), bytes.data() + expected_header.size(), 26 * sizeof(float));
  // Normals zero; red's three higher bands first, then green's, then blue's.
  const std::vector<float> expected = {1,   2,   3,   0,   0,   0,   100, 101, 102,
                                       110, 120, 130, 111, 121, 131, 112, 122, 132,
                                       11,  4,   5,   6,   7,   8,   9,   10};
  EXPECT_EQ(values, expected);
}

TEST(PlyIo, ReadsConformanceModel) {
  const fs::path file = conformance_ply();
  const GaussianModel m = read_ply(file);
  EXPECT_EQ(m.size(), 50000u);
  EXPECT_EQ(m.sh_degree, 3);
  EXPECT_NO_THROW(m.check_consistent());
  for (const std::vector<float>* a : {&m.means, &m.log_scales, &m.quats, &m.opacity_logits, &m.sh})
    EXPECT_TRUE(std::all_of(a->begin(), a->end(), [](float x) { return std::isfinite(x); }));

  // The last vertex against the raw bytes, decoded here with the layout rule.
  const std::string bytes = read_bytes(file);
  const std::size_t row_floats = 62;
  std::vector<float> last(row_floats);
  std::memcpy(last.data(), bytes.data() + bytes.size() - row_floats * sizeof(float),
              row_floats * sizeof(float));
  const std::size_t i = m.size() - 1;
  EXPECT_EQ(m.means[i * 3 + 2], last[2]);
  EXPECT_EQ(m.sh[(i * 16 + 0) * 3 + 1], last[7]);           // f_dc_1
  EXPECT_EQ(m.sh[(i * 16 + 1) * 3 + 0], last[9]);           // f_rest_0: red, band 1
  EXPECT_EQ(m.sh[(i * 16 + 1) * 3 + 1], last[9 + 15]);      // f_rest_15: green, band 1
  EXPECT_EQ(m.sh[(i * 16 + 15) * 3 + 2], last[9 + 44]);     // f_rest_44: blue, band 15
  EXPECT_EQ(m.opacity_logits[i], last[54]);
  EXPECT_EQ(m.quats[i * 4 + 3], last[61]);
}

TEST(PlyIo, RewritingConformanceModelReproducesTheFile) {
  const fs::path file = conformance_ply();
  const std::string original = read_bytes(file);
  const fs::path copy = test::scratch_dir("ply_conformance") / "copy.ply";
  write_ply(read_ply(file), copy);
  const std::string rewritten = read_bytes(copy);
  ASSERT_EQ(rewritten.size(), original.size());

  // We write zero normals; the official writer does too, so when the file's normals are zero
  // the whole file must come back byte for byte. Otherwise compare all but the normals.
  const std::size_t row_bytes = 62 * sizeof(float);
  const std::size_t data_offset = original.size() - 50000 * row_bytes;
  const std::size_t normals_begin = 3 * sizeof(float), normals_end = 6 * sizeof(float);
  bool normals_zero = true;
  for (std::size_t i = 0; i < 50000; ++i)
    for (std::size_t b = normals_begin; b < normals_end; ++b)
      normals_zero = normals_zero && original[data_offset + i * row_bytes + b] == 0;
  if (normals_zero) {
    EXPECT_TRUE(rewritten == original);
  } else {
    std::string a = original, b = rewritten;
    for (std::size_t i = 0; i < 50000; ++i)
      for (std::size_t k = normals_begin; k < normals_end; ++k)
        a[data_offset + i * row_bytes + k] = b[data_offset + i * row_bytes + k] = 0;
    EXPECT_TRUE(a == b);
  }
}

// ---- Other encodings, orders, extra properties and elements ----------------------------

TEST(PlyIo, ReadsAsciiInAnyOrderWithExtras) {
  // Degree 1, properties reversed, an extra uchar colour and an int, an element with a list
  // before the vertices, CRLF line ends and comments in the header.
  std::vector<Prop> props = official_props(1);
  std::reverse(props.begin(), props.end());
  props.insert(props.begin() + 3, {"uchar", "red"});
  props.push_back({"int", "label"});
  const Rows rows = distinct_rows(props, 2);
  std::string header = "ply\r\nformat ascii 1.0\r\ncomment written by hand\r\nobj_info none\r\n"
                       "element meta 2\r\nproperty list uchar int ids\r\nproperty float w\r\n";
  for (const char c : element_header("vertex", rows.size(), props))
    header += c == '\n' ? std::string("\r\n") : std::string(1, c);
  header += "end_header\r\n";
  const fs::path file = test::scratch_dir("ply_ascii") / "hand.ply";
  test::write_text(file, header + "3 1 2 3 0.5\n0 7\n" + ascii_rows(props, rows));

  const GaussianModel m = read_ply(file);
  EXPECT_EQ(m.sh_degree, 1);
  expect_model_matches(m, props, rows);
}

TEST(PlyIo, ReadsBigEndianInAnyOrderWithExtras) {
  // Degree 0, shuffled, extras of several sizes, a scalar element before the vertices whose
  // data must be skipped, and a list element after them that must be ignored.
  std::vector<Prop> props = {{"float", "rot_0"},   {"float", "rot_1"},   {"uchar", "red"},
                             {"float", "rot_2"},   {"float", "rot_3"},   {"float", "opacity"},
                             {"double", "extra"},  {"float", "z"},       {"float", "y"},
                             {"float", "x"},       {"short", "s"},       {"float", "scale_2"},
                             {"float", "scale_0"}, {"float", "scale_1"}, {"float", "f_dc_2"},
                             {"char", "t"},        {"float", "f_dc_0"},  {"float", "f_dc_1"},
                             {"uint32", "u"}};
  const Rows rows = distinct_rows(props, 3);
  const std::vector<Prop> camera = {{"float64", "fx"}, {"uint8", "id"}, {"int16", "k"}};
  const std::vector<Prop> camera_io = {{"double", "fx"}, {"uchar", "id"}, {"short", "k"}};
  const std::string text =
      "ply\nformat binary_big_endian 1.0\n" + element_header("camera", 2, camera) +
      element_header("vertex", rows.size(), props) +
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
      binary_rows(camera_io, distinct_rows(camera_io, 2), true) + binary_rows(props, rows, true) +
      "\x03" + std::string(12, '\0');
  const fs::path file = test::scratch_dir("ply_big_endian") / "hand.ply";
  test::write_text(file, text);

  const GaussianModel m = read_ply(file);
  EXPECT_EQ(m.sh_degree, 0);
  expect_model_matches(m, props, rows);
}

TEST(PlyIo, ReadsEmptyModel) {
  const fs::path file = test::scratch_dir("ply_empty") / "empty.ply";
  test::write_text(file, simple_ply(official_props(2), {}));
  const GaussianModel m = read_ply(file);
  EXPECT_EQ(m.size(), 0u);
  EXPECT_EQ(m.sh_degree, 2);
}

// ---- Bad input -------------------------------------------------------------------------

class PlyBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir(std::string("ply_bad_") +
                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  fs::path file_with(const std::string& text) {
    const fs::path file = dir_ / "bad.ply";
    test::write_text(file, text);
    return file;
  }
  fs::path dir_;
};

TEST_F(PlyBadInput, MissingFile) { expect_read_error(dir_ / "absent.ply", {"does not exist"}); }

TEST_F(PlyBadInput, WrongMagic) {
  expect_read_error(file_with("plx\nformat ascii 1.0\nend_header\n"), {"not a PLY file"});
  expect_read_error(file_with(""), {"not a PLY file"});
}

TEST_F(PlyBadInput, UnknownFormat) {
  expect_read_error(file_with("ply\nformat binary_middle_endian 1.0\nend_header\n"),
                    {"unknown PLY format", "binary_middle_endian"});
}

TEST_F(PlyBadInput, NoVertexElement) {
  expect_read_error(file_with("ply\nformat ascii 1.0\nelement face 0\nend_header\n"),
                    {"no 'vertex' element"});
}

TEST_F(PlyBadInput, TruncatedData) {
  const std::vector<Prop> props = official_props(3);
  std::string text = simple_ply(props, distinct_rows(props, 4));
  text.resize(text.size() - 1);
  expect_read_error(file_with(text), {"truncated", "4 vertex rows"});
}

TEST_F(PlyBadInput, VertexCountExceedingDataIsRejectedBeforeAllocating) {
  // 10 million rows of 248 bytes would be 2.5 GB: the size check must come first.
  const std::vector<Prop> props = official_props(3);
  const std::string header = "ply\nformat binary_little_endian 1.0\n" +
                             element_header("vertex", 10000000u, props) + "end_header\n";
  expect_read_error(file_with(header + std::string(16, '\0')), {"truncated", "10000000"});
  const std::string ascii = "ply\nformat ascii 1.0\n" +
                            element_header("vertex", 10000000u, props) + "end_header\n";
  expect_read_error(file_with(ascii + "1 2 3\n"), {"truncated", "10000000"});
}

TEST_F(PlyBadInput, MoreGaussiansThanAFileMayHoldAreRefusedWhateverTheFileSize) {
  const std::vector<Prop> props = official_props(3);
  for (const std::uint64_t count : {std::uint64_t(kMaxGaussiansInAFile) + 1, std::uint64_t(4000000000u),
                                    std::numeric_limits<std::uint64_t>::max()})
    for (const char* format : {"binary_little_endian", "ascii"}) {
      const std::string header = std::string("ply\nformat ") + format + " 1.0\n" +
                                 element_header("vertex", count, props) + "end_header\n";
      expect_read_error(file_with(header + std::string(16, '\0')),
                        {std::to_string(count) + " Gaussians, more than the 16777216 a model file may hold"});
    }
}

TEST_F(PlyBadInput, MissingRequiredProperty) {
  std::vector<Prop> props = official_props(0);
  std::erase_if(props, [](const Prop& p) { return p.name == "opacity"; });
  expect_read_error(file_with(simple_ply(props, distinct_rows(props, 2))),
                    {"missing", "'opacity'"});
}

TEST_F(PlyBadInput, RequiredPropertyNotFloat) {
  std::vector<Prop> props = official_props(0);
  props[0].type = "double";
  expect_read_error(file_with(simple_ply(props, distinct_rows(props, 2))),
                    {"'x'", "double", "float"});
}

TEST_F(PlyBadInput, NanValue) {
  const std::vector<Prop> props = official_props(0);
  Rows rows = distinct_rows(props, 3);
  rows[1][9] = std::nan("");  // opacity of vertex 1
  expect_read_error(file_with(simple_ply(props, rows)), {"NaN", "'opacity'", "vertex 1"});
}

TEST_F(PlyBadInput, InfValue) {
  const std::vector<Prop> props = official_props(0);
  Rows rows = distinct_rows(props, 3);
  rows[2][1] = -INFINITY;  // y of vertex 2
  expect_read_error(file_with(simple_ply(props, rows)), {"Inf", "'y'", "vertex 2"});
  const std::string ascii = "ply\nformat ascii 1.0\n" + element_header("vertex", 3, props) +
                            "end_header\n" + ascii_rows(props, rows);
  expect_read_error(file_with(ascii), {"Inf", "'y'", "vertex 2"});
}

TEST_F(PlyBadInput, UnsupportedRestCount) {
  std::vector<Prop> props = official_props(0);
  props.push_back({"float", "f_rest_9"});
  for (int j = 0; j < 9; ++j) props.push_back({"float", "f_rest_" + std::to_string(j)});
  expect_read_error(file_with(simple_ply(props, distinct_rows(props, 1))),
                    {"f_rest", "10"});
}

TEST_F(PlyBadInput, GarbageWithoutEndHeader) {
  std::mt19937 rng(5);
  std::string noise(100000, '\0');
  for (char& c : noise) {
    c = char(rng() & 0xff);
    if (c == '\n') c = ' ';
  }
  expect_read_error(file_with(noise), {"not a PLY file"});
  expect_read_error(file_with("ply\n" + noise), {"no end_header", "64 KiB"});
  expect_read_error(file_with("ply\nformat binary_little_endian 1.0\n" + std::string(20000, '\n')),
                    {"no end_header", "10000 lines"});
  expect_read_error(file_with("ply\nformat ascii 1.0\nelement vertex 1\n"), {"no end_header"});
  // Binary noise with line breaks reads as nonsense header lines.
  for (char& c : noise)
    if ((c & 0x3f) == 0) c = '\n';
  expect_read_error(file_with("ply\n" + noise), {"malformed PLY header"});
}

TEST_F(PlyBadInput, AsciiRowsWithTooFewOrNonNumericValues) {
  const std::vector<Prop> props = official_props(0);
  const std::string header =
      "ply\nformat ascii 1.0\n" + element_header("vertex", 2, props) + "end_header\n";
  const std::string good_row = ascii_rows(props, distinct_rows(props, 1));
  expect_read_error(file_with(header + good_row + "1 2 3\n"), {"vertex 1", "3 values"});
  std::string bad_row = good_row;
  bad_row.replace(0, bad_row.find(' '), "abc");
  expect_read_error(file_with(header + good_row + bad_row), {"vertex 1", "'x'", "not a number"});
  expect_read_error(file_with(header + good_row), {"truncated", "1 of 2"});
}

TEST_F(PlyBadInput, ListProperties) {
  std::vector<Prop> props = official_props(0);
  const std::string in_vertex = "ply\nformat binary_little_endian 1.0\n" +
                                element_header("vertex", 1, props) +
                                "property list uchar int ids\nend_header\n";
  expect_read_error(file_with(in_vertex + std::string(100, '\0')), {"'ids'", "list"});
  const std::string before_vertex = "ply\nformat binary_little_endian 1.0\nelement face 1\n"
                                    "property list uchar int ids\n" +
                                    element_header("vertex", 1, props) + "end_header\n";
  expect_read_error(file_with(before_vertex + std::string(100, '\0')), {"'face'", "list"});
}

TEST_F(PlyBadInput, MutatedFilesEitherReadOrThrowInputError) {
  // Random byte edits and cuts of small valid files: whatever they do to the header or the
  // data, reading must succeed or throw InputError, never crash, hang or throw anything else
  // (the sanitizer build turns memory errors into failures).
  const std::vector<Prop> props = official_props(1);
  const Rows rows = distinct_rows(props, 3);
  const std::string header = element_header("vertex", rows.size(), props) + "end_header\n";
  const std::vector<std::string> seeds = {
      simple_ply(props, rows),
      "ply\nformat ascii 1.0\n" + header + ascii_rows(props, rows),
      "ply\nformat binary_big_endian 1.0\n" + header + binary_rows(props, rows, true)};
  std::mt19937 rng(7);
  const char replacements[] = {'\n', ' ', '0', '9', '-', 'e', '\0', '\xff'};
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string text = seeds[trial % seeds.size()];
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rng() % text.size();
      if (rng() % 8 == 0) text.resize(at);
      else text[at] = rng() % 2 ? replacements[rng() % sizeof replacements] : char(rng());
      if (text.empty()) break;
    }
    try {
      read_ply(file_with(text));
      ++accepted;
    } catch (const InputError&) {
      ++rejected;
    }
  }
  // Both outcomes occur: edits inside values are harmless, edits in the header are not.
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

// ---- Writing failures -------------------------------------------------------------------

TEST(PlyIo, WriteIntoMissingFolderThrowsAndLeavesNothing) {
  const fs::path dir = test::scratch_dir("ply_write_missing");
  const fs::path file = dir / "no_such_folder" / "model.ply";
  EXPECT_THROW(write_ply(test::random_model(10, 1, 3), file), InputError);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_FALSE(fs::exists(file.parent_path()));
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(PlyIo, WriteInconsistentModelThrows) {
  GaussianModel m = test::random_model(10, 2, 4);
  m.sh.pop_back();
  const fs::path file = test::scratch_dir("ply_write_bad") / "model.ply";
  EXPECT_THROW(write_ply(m, file), ArgumentError);
  EXPECT_FALSE(fs::exists(file));
  m = test::random_model(10, 2, 4);
  m.sh_degree = 4;
  EXPECT_THROW(write_ply(m, file), ArgumentError);
}

}  // namespace
}  // namespace splat
