#pragma once
// Running the command-line tools from tests.
#include <filesystem>
#include <string>

namespace splat::test {

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `command` through the shell with stdout and stderr captured in files under `dir`.
CommandResult run_command(const std::string& command, const std::filesystem::path& dir);

std::string read_file(const std::filesystem::path& file);

// The last non-empty line of `text`.
std::string last_line(const std::string& text);

}  // namespace splat::test
