#pragma once
// Writing outputs so that a failure never leaves a half-written file: write to a temporary
// name in the same folder, then rename into place (docs/DESIGN.md, "Errors").
#include <filesystem>
#include <functional>
#include <ostream>

namespace splat {

// Calls write(temp_path); on success renames temp_path to `file`, on any exception removes
// the temporary and rethrows. The temporary keeps the final extension (tools such as
// OpenImageIO choose the format from it).
void write_atomically(const std::filesystem::path& file,
                      const std::function<void(const std::filesystem::path& temp_path)>& write);

// write_atomically through a binary stream: `write` fills it; the stream is then flushed and
// closed, and only if no write failed (a full disk, a file-size limit) is the file moved into
// place. Otherwise InputError naming `file` and the system's reason; the previous `file`, if
// any, is untouched. Checking after the close matters: the last buffered bytes are only
// written then.
void write_stream_atomically(const std::filesystem::path& file, const std::function<void(std::ostream& out)>& write);

// InputError when an output file's path names a folder: found before the work, not at the
// rename that ends it (after other outputs are written).
void check_output_file_path(const std::filesystem::path& file);

}  // namespace splat
