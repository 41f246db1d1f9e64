// Every numeric option has a range, documented in DESIGN §5's table and checked where the
// option is read. This test reads the table and gives each option the nearest values outside
// both ends: each call is refused with the table's range in
// one error line, before anything is loaded or made. So the table and the code cannot drift
// apart, and an option added with a range must be added to the table to be tested.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli_support.hpp"
#include "tests/test_support.hpp"

namespace splat {
namespace {

namespace fs = std::filesystem;

struct RangeRow {
  std::string program, option, kind;
  double from = 0, to = 0;
};

std::string trim(const std::string& text) {
  const std::size_t first = text.find_first_not_of(' '), last = text.find_last_not_of(' ');
  return first == std::string::npos ? "" : text.substr(first, last - first + 1);
}

// The rows "| splat-x | --option | kind | from | to | note |" of DESIGN.md.
std::vector<RangeRow> documented_ranges() {
  std::ifstream in(fs::path(SPLAT_SOURCE_DIR) / "docs" / "DESIGN.md");
  std::vector<RangeRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| splat-", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream cells_text(line.substr(1));
    for (std::string cell; std::getline(cells_text, cell, '|');) cells.push_back(trim(cell));
    if (cells.size() < 5 || cells[1].rfind("--", 0) != 0) continue;
    rows.push_back({cells[0], cells[1], cells[2], std::stod(cells[3]), std::stod(cells[4])});
  }
  return rows;
}

// "%g" with enough digits for the table's values.
std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

TEST(OptionRanges, EveryDocumentedRangeIsCheckedWhereTheOptionIsRead) {
  const fs::path dir = test::scratch_dir("option_ranges");
  test::write_text(dir / "cameras.json", R"({"camera_angle_x": 0.7, "frames": [{"file_path": "v0",
    "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]}]})");
  const std::string d = dir.string();
  // What each program needs besides the option for the option to be read (files that do not
  // exist are never opened: the ranges are checked first).
  const std::map<std::string, std::string> program = {
      {"splat-train", std::string(SPLAT_TRAIN_EXE) + " --data " + d + "/no_data --out " + d + "/out"},
      {"splat-eval", std::string(SPLAT_EVAL_EXE) + " --data " + d + "/no_data --out " + d + "/out"},
      {"splat-render", std::string(SPLAT_RENDER_EXE) + " --model " + d + "/no.ply --cameras " + d +
                           "/cameras.json --out " + d + "/out"},
      {"splat-viewer", std::string(SPLAT_VIEWER_EXE) + " " + d + "/no.ply --cameras " + d + "/cameras.json"},
      {"splat-grad", std::string(SPLAT_GRAD_EXE) + " --model " + d + "/no.ply --cameras " + d +
                         "/cameras.json --weights " + d + "/no.f32 --out " + d + "/out.f32 --view 0 --width 8 "
                         "--height 8 --bg white"},
      {"splat-process", std::string(SPLAT_PROCESS_EXE) + " --video " + d + "/no.mp4 --out " + d + "/out"},
      {"splat-convert", std::string(SPLAT_CONVERT_EXE) + " " + d + "/no.ply " + d + "/out.spz"},
      {"splat-demo", std::string(SPLAT_DEMO_EXE) + " --out " + d + "/out"},
      {"splat-scene", std::string(SPLAT_SCENE_EXE) + " render " + d + "/no_scene.json --out " + d + "/out"},
  };
  // Options read only beside another one.
  const std::map<std::string, std::string> companion = {
      {"splat-render --frames", "--path orbit --video " + d + "/out.mp4"},
      {"splat-render --fps", "--path orbit --video " + d + "/out.mp4"},
      {"splat-eval --stability-views", "--stability"},
      {"splat-eval --pose-noise", "--stability"},
  };
  const std::vector<RangeRow> rows = documented_ranges();
  ASSERT_GE(rows.size(), 40u) << "DESIGN.md's table of option ranges was not found";
  for (const RangeRow& row : rows) {
    SCOPED_TRACE(row.program + " " + row.option);
    ASSERT_TRUE(program.count(row.program)) << "no command line for " << row.program;
    const bool whole = row.kind.find("whole") != std::string::npos;
    const std::size_t count = row.kind.rfind("2 ", 0) == 0 ? 2 : 1;
    const std::string range = std::string(whole ? "a whole number" : "a number") + " from " +
                              number_text(row.from) + " to " + number_text(row.to);
    const double below = whole || row.from == 0 ? row.from - 1 : row.from / 2;
    for (const std::string& value : {number_text(below), number_text(row.to + 1)}) {
      std::string values = value;
      for (std::size_t k = 1; k < count; ++k) values += "," + value;
      const auto extra = companion.find(row.program + " " + row.option);
      const std::string command = program.at(row.program) + " " +
                                  (extra == companion.end() ? "" : extra->second + " ") + row.option + " " + values;
      const test::CommandResult r = test::run_command(command, dir);
      EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
      EXPECT_EQ(r.err.rfind("error: option " + row.option + " must be ", 0), 0u) << command << "\n" << r.err;
      EXPECT_NE(r.err.find(range), std::string::npos) << command << "\nexpected: " << range << "\ngot: " << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << command << "\n" << r.err;
    }
  }
  EXPECT_FALSE(fs::exists(dir / "out")) << "a refused call made its output folder";
}

}  // namespace
}  // namespace splat
