#pragma once
// A small "--name value" / "--name=value" / "--flag" command-line parser, the same for every
// program: "-h" is "--help" (where there is one), "--version" prints the program's name and
// the project's version and exits 0. Unknown options (with the nearest known one suggested),
// missing values and malformed numbers raise splat::ArgumentError, which run_main turns into
// exit status 2.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "splat/core/setting_value.hpp"

namespace splat::cli {

// Ranges more than one program's options share.
constexpr SettingRange kThreadsRange{1, 4096};
constexpr SettingRange kImageSideRange{1, 16384};
constexpr SettingRange kShDegreeRange{0, 3};
constexpr SettingRange kViewIndexRange{0, 999999};  // --view: checked against the cameras later

class ArgParser {
 public:
  // `value_options` take one value ("--out DIR"); `flag_options` take none ("--help").
  // Words that are not options are collected as positionals.
  ArgParser(int argc, char** argv, std::vector<std::string> value_options,
            std::vector<std::string> flag_options);

  bool has(const std::string& name) const;
  std::optional<std::string> value(const std::string& name) const;
  std::string required(const std::string& name) const;
  // Numeric options state the values they allow, a closed range, where they are read (and
  // in their --help and DESIGN §5's table): anything else, malformed or outside it, is
  // ArgumentError "option --NAME must be a whole number from LO to HI, got 'V'".
  std::optional<int> integer(const std::string& name, SettingRange range) const;
  std::optional<double> number(const std::string& name, SettingRange range) const;
  // "A,B,C": each value as integer() / number() takes it; exactly `count` of them when count > 0.
  std::optional<std::vector<long long>> integer_list(const std::string& name, SettingRange range,
                                                     std::size_t count = 0) const;
  std::optional<std::vector<double>> number_list(const std::string& name, SettingRange range,
                                                 std::size_t count = 0) const;
  // "a,b,,c" → {"a", "b", "", "c"}: the words between commas, empty ones included.
  std::optional<std::vector<std::string>> words(const std::string& name) const;
  // A colour, the one syntax every program's --bg takes: "white", "black", or "R,G,B" with each
  // component in [0, 1] (e.g. --bg 0.5,0.5,0.5); ArgumentError for anything else.
  std::optional<std::array<float, 3>> colour(const std::string& name) const;
  const std::vector<std::string>& positionals() const { return positionals_; }
  // ArgumentError naming the first word that is not an option, for tools that take none.
  void expect_no_positionals() const;

 private:
  std::vector<std::pair<std::string, std::string>> values_;
  std::vector<std::string> flags_;
  std::vector<std::string> positionals_;
};

}  // namespace splat::cli
