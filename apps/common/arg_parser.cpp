#include "apps/common/arg_parser.hpp"

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "splat/core/error.hpp"

namespace splat::cli {

namespace {
bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Edits (insertions, deletions, substitutions) between two names.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// " (did you mean --x?)" for the option nearest `name`, when it is near enough to be a slip.
std::string suggestion(const std::string& name, const std::vector<std::string>& value_options,
                       const std::vector<std::string>& flag_options) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const auto* options : {&value_options, &flag_options})
    for (const std::string& option : *options)
      if (const std::size_t d = edit_distance(name, option); d < best_distance) best_distance = d, best = option;
  return best.empty() ? " (see --help)" : " (did you mean --" + best + "?)";
}
}  // namespace

ArgParser::ArgParser(int argc, char** argv, std::vector<std::string> value_options,
                     std::vector<std::string> flag_options) {
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "-h" && contains(flag_options, "help")) {
      flags_.push_back("help");
      continue;
    }
    if (word == "--version") {
      std::printf("%s %s\n", std::filesystem::path(argv[0]).filename().c_str(), SPLAT_VERSION);
      std::fflush(stdout);
      std::exit(0);
    }
    if (word.rfind("--", 0) != 0 || word.size() == 2) {
      positionals_.push_back(word);
      continue;
    }
    // "--name=value" is "--name value".
    const std::size_t equals = word.find('=');
    const std::string name = word.substr(2, equals == std::string::npos ? std::string::npos : equals - 2);
    if (contains(flag_options, name)) {
      if (equals != std::string::npos) throw ArgumentError("option --" + name + " takes no value");
      flags_.push_back(name);
    } else if (contains(value_options, name)) {
      if (equals != std::string::npos) {
        values_.emplace_back(name, word.substr(equals + 1));
        continue;
      }
      if (i + 1 >= argc) throw ArgumentError("option --" + name + " needs a value");
      values_.emplace_back(name, argv[++i]);
    } else {
      throw ArgumentError("unknown option --" + name + suggestion(name, value_options, flag_options));
    }
  }
}

void ArgParser::expect_no_positionals() const {
  if (!positionals_.empty()) throw ArgumentError("unexpected argument '" + positionals_.front() + "'");
}

bool ArgParser::has(const std::string& name) const {
  return contains(flags_, name) || value(name).has_value();
}

std::optional<std::string> ArgParser::value(const std::string& name) const {
  // The last occurrence wins, as in most command lines.
  for (auto it = values_.rbegin(); it != values_.rend(); ++it)
    if (it->first == name) return it->second;
  return std::nullopt;
}

std::string ArgParser::required(const std::string& name) const {
  auto v = value(name);
  if (!v) throw ArgumentError("missing required option --" + name + " (see --help)");
  return *v;
}

namespace {

// The message every numeric option gives for a value it does not take.
ArgumentError out_of_range(const std::string& name, bool whole, const SettingRange& range, const std::string& text,
                           std::size_t count) {
  const std::string values = count == 1   ? ""
                             : count > 1  ? std::to_string(count) + " comma-separated values, each "
                                          : "comma-separated values, each ";
  return ArgumentError("option --" + name + " must be " + values + setting_range_text(whole, range) +
                       ", got '" + text + "'");
}

// The words of "a,b,c" (one empty word for "", so that it fails as a number).
std::vector<std::string> comma_separated(const std::string& text) {
  std::vector<std::string> words;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    words.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return words;
    start = comma + 1;
  }
}

// `word` as a number within `range` (whole when `whole`), or nullopt.
std::optional<double> parse_in_range(const std::string& word, bool whole, const SettingRange& range) {
  // Decimal only (from_chars reads no hex, no leading blanks and no "+"), and every character.
  double parsed = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), parsed);
  if (word.empty() || error != std::errc() || end != word.data() + word.size() || !std::isfinite(parsed) ||
      parsed < range.lo || parsed > range.hi || (whole && parsed != std::floor(parsed)))
    return std::nullopt;
  return parsed;
}

// The values of option `name`: `count` of them (any number when 0), each in `range`.
std::optional<std::vector<double>> values_in_range(const std::optional<std::string>& text, const std::string& name,
                                                   bool whole, const SettingRange& range, std::size_t count) {
  if (!text) return std::nullopt;
  const std::vector<std::string> words = count == 1 ? std::vector<std::string>{*text} : comma_separated(*text);
  if (count > 0 && words.size() != count) throw out_of_range(name, whole, range, *text, count);
  std::vector<double> values;
  for (const std::string& word : words) {
    const std::optional<double> value = parse_in_range(word, whole, range);
    if (!value) throw out_of_range(name, whole, range, *text, count);
    values.push_back(*value);
  }
  return values;
}

}  // namespace

std::optional<int> ArgParser::integer(const std::string& name, SettingRange range) const {
  const auto values = values_in_range(value(name), name, true, range, 1);
  if (!values) return std::nullopt;
  return int(values->front());
}

std::optional<double> ArgParser::number(const std::string& name, SettingRange range) const {
  const auto values = values_in_range(value(name), name, false, range, 1);
  if (!values) return std::nullopt;
  return values->front();
}

std::optional<std::vector<long long>> ArgParser::integer_list(const std::string& name, SettingRange range,
                                                              std::size_t count) const {
  const auto values = values_in_range(value(name), name, true, range, count);
  if (!values) return std::nullopt;
  return std::vector<long long>(values->begin(), values->end());
}

std::optional<std::vector<double>> ArgParser::number_list(const std::string& name, SettingRange range,
                                                          std::size_t count) const {
  return values_in_range(value(name), name, false, range, count);
}

std::optional<std::vector<std::string>> ArgParser::words(const std::string& name) const {
  const auto text = value(name);
  if (!text) return std::nullopt;
  return comma_separated(*text);
}

std::optional<std::array<float, 3>> ArgParser::colour(const std::string& name) const {
  auto v = value(name);
  if (!v) return std::nullopt;
  if (*v == "white") return std::array<float, 3>{1, 1, 1};
  if (*v == "black") return std::array<float, 3>{0, 0, 0};
  try {
    const std::vector<double> c = *values_in_range(v, name, false, {0, 1}, 3);
    return std::array<float, 3>{float(c[0]), float(c[1]), float(c[2])};
  } catch (const ArgumentError&) {
    throw ArgumentError("option --" + name + " expects white, black or R,G,B with each in [0, 1], got '" + *v + "'");
  }
}

}  // namespace splat::cli
