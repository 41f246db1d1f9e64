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

namespace splat::cli {

class ArgParser {
 public:
  // `value_options` take one value ("--out DIR"); `flag_options` take none ("--help").
  // Words that are not options are collected as positionals.
  ArgParser(int argc, char** argv, std::vector<std::string> value_options,
            std::vector<std::string> flag_options);

  bool has(const std::string& name) const;
  std::optional<std::string> value(const std::string& name) const;
  std::string required(const std::string& name) const;
  std::optional<int> integer(const std::string& name) const;
  // As integer(), and ArgumentError "--name must be >= 1" for a smaller value (counts,
  // thread numbers, factors).
  std::optional<int> positive_integer(const std::string& name) const;
  std::optional<double> number(const std::string& name) const;
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
