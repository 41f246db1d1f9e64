#pragma once
// A small "--name value" / "--name=value" / "--flag" command-line parser, the same for every
// program: "-h" is "--help" (where there is one), "--version" prints the program's name and
// the project's version and exits 0. Unknown options (with the nearest known one suggested),
// missing values and malformed numbers raise splat::ArgumentError, which run_main turns into
// exit status 2.
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
  // "R,G,B" with each in [0, 1], e.g. --bg 1,1,1.
  std::optional<std::vector<float>> float_list(const std::string& name, std::size_t count) const;
  const std::vector<std::string>& positionals() const { return positionals_; }
  // ArgumentError naming the first word that is not an option, for tools that take none.
  void expect_no_positionals() const;

 private:
  std::vector<std::pair<std::string, std::string>> values_;
  std::vector<std::string> flags_;
  std::vector<std::string> positionals_;
};

}  // namespace splat::cli
