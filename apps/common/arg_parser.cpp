#include "apps/common/arg_parser.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "splat/core/error.hpp"

namespace splat::cli {

namespace {
bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}
}  // namespace

ArgParser::ArgParser(int argc, char** argv, std::vector<std::string> value_options,
                     std::vector<std::string> flag_options) {
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.rfind("--", 0) != 0 || word.size() == 2) {
      positionals_.push_back(word);
      continue;
    }
    const std::string name = word.substr(2);
    if (contains(flag_options, name)) {
      flags_.push_back(name);
    } else if (contains(value_options, name)) {
      if (i + 1 >= argc) throw ArgumentError("option --" + name + " needs a value");
      values_.emplace_back(name, argv[++i]);
    } else {
      throw ArgumentError("unknown option --" + name + " (see --help)");
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

std::optional<std::vector<float>> ArgParser::float_list(const std::string& name,
                                                        std::size_t count) const {
  auto v = value(name);
  if (!v) return std::nullopt;
  std::vector<float> out;
  std::size_t start = 0;
  while (start <= v->size()) {
    const std::size_t comma = std::min(v->find(',', start), v->size());
    const std::string part = v->substr(start, comma - start);
    char* end = nullptr;
    const double parsed = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(parsed))
      throw ArgumentError("option --" + name + " expects " + std::to_string(count) +
                          " comma-separated numbers, got '" + *v + "'");
    out.push_back(float(parsed));
    start = comma + 1;
  }
  if (out.size() != count)
    throw ArgumentError("option --" + name + " expects " + std::to_string(count) +
                        " comma-separated numbers, got '" + *v + "'");
  return out;
}

}  // namespace splat::cli
