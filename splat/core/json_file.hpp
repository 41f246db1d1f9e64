#pragma once
// JSON files, and JSON errors in the project's form: one line naming the file and the
// problem, without nlohmann's "[json.exception.parse_error.101] " prefix.
#include <exception>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace splat {

// "parse error at line 3, column 5: ..." from "[json.exception.parse_error.101] parse error at
// line 3, column 5: ...": the prefix identifies the library's exception class, which says
// nothing to a user.
std::string json_error_text(const std::exception& e);
// The same for a message another library passed on (tinygltf's parse errors).
std::string json_error_text(const std::string& message);

enum class JsonComments { kRefused, kAllowed };

// The whole file, parsed. InputError naming the file when it is missing, a folder, unreadable,
// or not JSON; `kind` names what the file should be in those messages ("config file").
nlohmann::json read_json_file(const std::filesystem::path& file, const std::string& kind = "JSON file",
                              JsonComments comments = JsonComments::kRefused);

}  // namespace splat
