#include "result_files.hpp"

#include <fstream>

#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"

namespace splat::cli {

void write_json_file(const std::filesystem::path& file, const nlohmann::json& json) {
  write_atomically(file, [&](const std::filesystem::path& temp) {
    std::ofstream out(temp);
    out << json.dump(1) << "\n";
    if (!out) throw InputError(file, "cannot write the file");
  });
}

std::optional<nlohmann::json> read_json_if_present(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return std::nullopt;
  std::ifstream in(file);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed JSON: ") + e.what());
  }
}

std::string method_label(const nlohmann::json& run) {
  const std::string method = run.value("method", "splat");
  if (method == "nerf") return "NeRF";
  if (run.contains("strategy")) return "splat (" + run["strategy"].get<std::string>() + ")";
  return method;
}

}  // namespace splat::cli
