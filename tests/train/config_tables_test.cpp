// docs/DESIGN.md §4.7 lists every key of both trainers' config files with its default; this
// test reads those tables and compares them with what to_json writes for a default config (the
// splat table's "Official" and "Compact" columns, the NeRF's "Default"), so the document
// cannot drift from the code: a key the code writes and the table lacks, a key the table
// names and the code does not write, or a default that differs, fails.
//
// The tables' cells, as the test reads them:
// - Key: keys in backticks, separated by commas; a key that starts with `_` or `.` continues
//   the one before it, replacing what follows its last `_` or `.` (`background_r`, `_g`, `_b`).
//   Keys of a nested object are dotted (`model.coarse.depth`).
// - Values: one per key, separated by commas: numbers (`−` or `-` for minus), true, false, a
//   string in quotes (backticks around it allowed), or an array `[1, 1, 1]`. An empty
//   "Compact" cell means the same as "Official".
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "splat/train/nerf_training_config.hpp"
#include "splat/train/training_config.hpp"

namespace splat {
namespace {

using Row = std::vector<std::string>;  // a table row's cells, trimmed

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

std::string read_design() {
  std::ifstream in(std::filesystem::path(SPLAT_SOURCE_DIR) / "docs" / "DESIGN.md", std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The rows (header and separator left out) of the table in §4.7 whose header starts with
// `header`, e.g. "| Key | Default |".
std::vector<Row> design_table(const std::string& header) {
  const std::string design = read_design();
  const std::size_t section = design.find("\n### 4.7 ");
  if (section == std::string::npos) return {};
  const std::size_t end = design.find("\n### ", section + 1);
  std::istringstream lines(design.substr(section, end - section));
  std::vector<Row> rows;
  bool inside = false;
  for (std::string line; std::getline(lines, line);) {
    if (!inside) {
      inside = line.rfind(header, 0) == 0;
      if (inside) std::getline(lines, line);  // the |---| line
      continue;
    }
    if (line.empty() || line[0] != '|') break;
    Row row;
    std::string cell;
    std::istringstream cells(line.substr(1));
    while (std::getline(cells, cell, '|')) row.push_back(trim(cell));
    rows.push_back(row);
  }
  return rows;
}

// Splits a cell at the commas outside brackets.
std::vector<std::string> split_list(const std::string& cell) {
  std::vector<std::string> items;
  std::string item;
  int depth = 0;
  for (char c : cell) {
    if (c == '[') ++depth;
    if (c == ']') --depth;
    if (c == ',' && depth == 0) {
      items.push_back(trim(item));
      item.clear();
    } else {
      item += c;
    }
  }
  if (!trim(item).empty() || !items.empty()) items.push_back(trim(item));
  return items;
}

std::vector<std::string> keys_of(const std::string& cell) {
  std::vector<std::string> keys;
  for (std::string key : split_list(cell)) {
    if (key.size() < 2 || key.front() != '`' || key.back() != '`') {
      ADD_FAILURE() << "not a key in backticks: " << key;
      continue;
    }
    key = key.substr(1, key.size() - 2);
    if (!keys.empty() && (key[0] == '_' || key[0] == '.')) {
      const std::string& before = keys.back();
      key = before.substr(0, before.rfind(key[0])) + key;
    }
    keys.push_back(key);
  }
  return keys;
}

// A value as the table writes it, as JSON.
nlohmann::json parse_value(std::string text) {
  if (text.size() >= 2 && text.front() == '`' && text.back() == '`') text = text.substr(1, text.size() - 2);
  for (std::size_t at; (at = text.find("−")) != std::string::npos;) text.replace(at, std::string("−").size(), "-");
  if (text == "true" || text == "false" || (!text.empty() && (text[0] == '"' || text[0] == '[')))
    return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') return nlohmann::json::value_t::discarded;
  return number;
}

// Numbers equal to float precision (the code keeps most settings as float).
bool same_value(const nlohmann::json& table, const nlohmann::json& code) {
  if (table.is_number() && code.is_number()) {
    const double a = table.get<double>(), b = code.get<double>();
    return a == b || std::abs(a - b) <= 1e-6 * std::abs(a);
  }
  if (table.is_array() && code.is_array() && table.size() == code.size()) {
    for (std::size_t i = 0; i < table.size(); ++i)
      if (!same_value(table[i], code[i])) return false;
    return true;
  }
  return table == code;
}

// Nested objects as dotted keys.
void flatten(const nlohmann::json& json, const std::string& prefix, std::map<std::string, nlohmann::json>& out) {
  for (const auto& [key, value] : json.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    if (value.is_object()) flatten(value, name, out);
    else out[name] = value;
  }
}

std::map<std::string, nlohmann::json> flat(const nlohmann::json& json) {
  std::map<std::string, nlohmann::json> out;
  flatten(json, "", out);
  return out;
}

// Compares one column (`column`, 1-based after the keys; `fallback` the column an empty cell
// stands for, or 0) of `rows` with `code`, and every key of `code` with the table's.
void expect_table_matches(const std::vector<Row>& rows, std::size_t column, std::size_t fallback,
                          const nlohmann::json& code_json, const std::string& what) {
  ASSERT_FALSE(rows.empty()) << what << ": no table found in docs/DESIGN.md §4.7";
  const auto code = flat(code_json);
  std::map<std::string, int> documented;
  for (const Row& row : rows) {
    ASSERT_GT(row.size(), std::max(column, fallback)) << what << ": a short row";
    const std::vector<std::string> keys = keys_of(row[0]);
    const std::string& cell = row[column].empty() && fallback > 0 ? row[fallback] : row[column];
    const std::vector<std::string> values = split_list(cell);
    ASSERT_EQ(values.size(), keys.size()) << what << ": " << row[0] << " has " << values.size()
                                          << " values in \"" << cell << "\"";
    for (std::size_t i = 0; i < keys.size(); ++i) {
      ++documented[keys[i]];
      const auto it = code.find(keys[i]);
      if (it == code.end()) {
        ADD_FAILURE() << what << ": DESIGN names \"" << keys[i] << "\", which the config does not write";
        continue;
      }
      const nlohmann::json table_value = parse_value(values[i]);
      EXPECT_FALSE(table_value.is_discarded()) << what << ": \"" << keys[i] << "\": cannot read " << values[i];
      EXPECT_TRUE(same_value(table_value, it->second))
          << what << ": \"" << keys[i] << "\" is " << values[i] << " in DESIGN, " << it->second.dump() << " in the code";
    }
  }
  for (const auto& [key, value] : code) {
    EXPECT_TRUE(documented.count(key)) << what << ": \"" << key << "\" (" << value.dump() << ") is not in DESIGN";
    EXPECT_LE(documented[key], 1) << what << ": \"" << key << "\" is in DESIGN twice";
  }
}

TEST(ConfigTables, DesignListsEverySplatSettingWithItsDefaultAndTheCompactPreset) {
  const std::vector<Row> rows = design_table("| Key | Official | Compact |");
  expect_table_matches(rows, 1, 0, to_json(splat_training_preset("official")), "official");
  expect_table_matches(rows, 2, 1, to_json(splat_training_preset("compact")), "compact");
}

TEST(ConfigTables, DesignListsEveryNerfSettingWithItsDefaultAndTheNgpPreset) {
  const std::vector<Row> rows = design_table("| Key | NeRF | NGP |");
  expect_table_matches(rows, 1, 0, to_json(nerf_training_preset("nerf")), "NeRF");
  expect_table_matches(rows, 2, 1, to_json(nerf_training_preset("ngp")), "NGP");
  EXPECT_EQ(to_json(nerf_training_preset("nerf")), to_json(NerfTrainingConfig{}));
}

// The reader of the tables fails when they disagree with the code.
TEST(ConfigTables, TheCheckFindsAWrongDefaultAMissingKeyAndAnUnknownOne) {
  const nlohmann::json code = {{"a", 1}, {"b_x", 0.25}, {"b_y", true}, {"m", {{"c", "x"}, {"d", {1, 2, 3}}}}};
  const std::vector<Row> good = {{"`a`", "1"}, {"`b_x`, `_y`", "0.25, true"}, {"`m.c`, `.d`", "`\"x\"`, [1, 2, 3]"}};
  expect_table_matches(good, 1, 0, code, "good");
  const auto failures = [&](const std::vector<Row>& rows) {
    ::testing::TestPartResultArray results;
    {
      ::testing::ScopedFakeTestPartResultReporter reporter(
          ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
      expect_table_matches(rows, 1, 0, code, "bad");
    }
    return results.size();
  };
  EXPECT_EQ(failures(good), 0);
  EXPECT_GT(failures({{"`a`", "2"}, {"`b_x`, `_y`", "0.25, true"}, {"`m.c`, `.d`", "\"x\", [1, 2, 3]"}}), 0);
  EXPECT_GT(failures({{"`b_x`, `_y`", "0.25, true"}, {"`m.c`, `.d`", "\"x\", [1, 2, 3]"}}), 0);
  EXPECT_GT(failures({{"`a`, `z`", "1, 1"}, {"`b_x`, `_y`", "0.25, true"}, {"`m.c`, `.d`", "\"x\", [1, 2, 3]"}}), 0);
  EXPECT_GT(failures({{"`a`", "1"}, {"`b_x`, `_y`", "0.25, true"}, {"`m.c`, `.d`", "\"x\", [1, 2, 4]"}}), 0);
}

}  // namespace
}  // namespace splat
