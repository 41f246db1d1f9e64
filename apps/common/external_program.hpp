#pragma once
// Running the outside programs some tools drive (COLMAP, ffmpeg) without a shell: arguments
// go through as they are (no quoting), output goes to a log file the user can read.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace splat::cli {

// Whether `name` is an executable file in a folder of PATH.
bool program_on_path(const std::string& name);

// Runs `arguments` (arguments[0] looked up on PATH) with stdout and stderr appended to `log`,
// and waits, calling `while_running` (when given) about four times a second meanwhile, to
// report progress from the log. Returns the exit status (128 + signal when killed).
// ArgumentError when it cannot be started.
int run_program(const std::vector<std::string>& arguments, const std::filesystem::path& log,
                const std::function<void()>& while_running = {});

// The last non-empty line of `file`, trimmed (empty when it cannot be read), for a one-line
// error message.
std::string last_line_of_file(const std::filesystem::path& file);

}  // namespace splat::cli
