#pragma once
// Writing outputs so that a failure never leaves a half-written file: write to a temporary
// name in the same folder, then rename into place (docs/DESIGN.md, "Errors").
#include <filesystem>
#include <functional>

namespace splat {

// Calls write(temp_path); on success renames temp_path to `file`, on any exception removes
// the temporary and rethrows. The temporary keeps the final extension (tools such as
// OpenImageIO choose the format from it).
void write_atomically(const std::filesystem::path& file,
                      const std::function<void(const std::filesystem::path& temp_path)>& write);

}  // namespace splat
