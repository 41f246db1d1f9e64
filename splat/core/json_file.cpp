#include "splat/core/json_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "splat/core/error.hpp"

namespace splat {

std::string json_error_text(const std::exception& e) { return json_error_text(std::string(e.what())); }

std::string json_error_text(const std::string& message) {
  if (message.rfind("[json.exception.", 0) != 0) return message;
  const std::size_t end = message.find("] ");
  return end == std::string::npos ? message : message.substr(end + 2);
}

nlohmann::json read_json_file(const std::filesystem::path& file, const std::string& kind,
                              JsonComments comments) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw InputError(file, "file does not exist");
  if (std::filesystem::is_directory(file, ec)) throw InputError(file, "is a folder, not a " + kind);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, std::string("cannot open the file: ") + std::strerror(errno));
  std::stringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(file, "cannot read the file");
  try {
    return nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/true,
                                 /*ignore_comments=*/comments == JsonComments::kAllowed);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "malformed JSON: " + json_error_text(e));
  }
}

}  // namespace splat
