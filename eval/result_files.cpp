#include "result_files.hpp"

#include <fstream>

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"

namespace splat::cli {

namespace {

// "key 'history' not found" from "[json.exception.out_of_range.403] key 'history' not found".
std::string without_exception_id(const std::string& message) {
  if (message.rfind("[json.exception.", 0) != 0) return message;
  const std::size_t end = message.find("] ");
  return end == std::string::npos ? message : message.substr(end + 2);
}

}  // namespace

void write_json_file(const std::filesystem::path& file, const nlohmann::json& json) {
  write_stream_atomically(file, [&](std::ostream& out) { out << json.dump(1) << "\n"; });
}

std::optional<nlohmann::json> read_json_if_present(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return std::nullopt;
  std::ifstream in(file);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "malformed JSON: " + without_exception_id(e.what()));
  }
}


void with_result_file(const std::filesystem::path& file, const std::function<void(const nlohmann::json&)>& use) {
  const std::optional<nlohmann::json> json = read_json_if_present(file);
  if (!json) return;
  try {
    use(*json);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "not a splat-eval result file as expected: " + without_exception_id(e.what()));
  }
}

std::string method_label(const nlohmann::json& run) {
  const std::string method = run.value("method", "splat");
  if (method == "nerf") return "NeRF";
  if (run.contains("strategy")) return "splat (" + run["strategy"].get<std::string>() + ")";
  return method;
}

}  // namespace splat::cli
