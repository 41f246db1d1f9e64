#include "apps/common/arg_parser.hpp"

#include <algorithm>
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

std::optional<int> ArgParser::integer(const std::string& name) const {
  auto v = value(name);
  if (!v) return std::nullopt;
  errno = 0;
  char* end = nullptr;
  const long parsed = std::strtol(v->c_str(), &end, 10);
  if (v->empty() || *end != '\0' || errno == ERANGE || parsed < -2147483647L || parsed > 2147483647L)
    throw ArgumentError("option --" + name + " expects an integer, got '" + *v + "'");
  return int(parsed);
}

std::optional<int> ArgParser::positive_integer(const std::string& name) const {
  const std::optional<int> n = integer(name);
  if (n && *n < 1) throw ArgumentError("--" + name + " must be >= 1");
  return n;
}

std::optional<double> ArgParser::number(const std::string& name) const {
  auto v = value(name);
  if (!v) return std::nullopt;
  char* end = nullptr;
  const double parsed = std::strtod(v->c_str(), &end);
  if (v->empty() || *end != '\0' || !std::isfinite(parsed))
    throw ArgumentError("option --" + name + " expects a number, got '" + *v + "'");
  return parsed;
}

std::optional<std::array<float, 3>> ArgParser::colour(const std::string& name) const {
  auto v = value(name);
  if (!v) return std::nullopt;
  if (*v == "white") return std::array<float, 3>{1, 1, 1};
  if (*v == "black") return std::array<float, 3>{0, 0, 0};
  const auto malformed = [&] {
    return ArgumentError("option --" + name + " expects white, black or R,G,B with each in [0, 1], got '" +
                         *v + "'");
  };
  std::array<float, 3> out{};
  std::size_t count = 0, start = 0;
  while (start <= v->size()) {
    const std::size_t comma = std::min(v->find(',', start), v->size());
    const std::string part = v->substr(start, comma - start);
    char* end = nullptr;
    const double parsed = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !(parsed >= 0 && parsed <= 1) || count == 3) throw malformed();
    out[count++] = float(parsed);
    start = comma + 1;
  }
  if (count != 3) throw malformed();
  return out;
}

}  // namespace splat::cli
