#include "apps/splat-eval/result_files.hpp"

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"
#include "splat/core/json_file.hpp"

namespace splat::cli {


void write_json_file(const std::filesystem::path& file, const nlohmann::json& json) {
  write_stream_atomically(file, [&](std::ostream& out) { out << json.dump(1) << "\n"; });
}

std::optional<nlohmann::json> read_json_if_present(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return std::nullopt;
  return read_json_file(file, "result file");
}


void with_result_file(const std::filesystem::path& file, const std::function<void(const nlohmann::json&)>& use) {
  const std::optional<nlohmann::json> json = read_json_if_present(file);
  if (!json) return;
  try {
    use(*json);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "not a splat-eval result file as expected: " + json_error_text(e));
  }
}

std::string method_label(const nlohmann::json& run) {
  const std::string method = run.value("method", "splat");
  if (method == "nerf") return "NeRF";
  if (method == "ngp") return "NGP";
  if (run.contains("strategy")) return "splat (" + run["strategy"].get<std::string>() + ")";
  return method;
}

}  // namespace splat::cli
