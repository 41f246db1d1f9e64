#pragma once
// splat-eval's JSON result files: written through a temporary name (never half-written),
// read back by the charts and the report.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

namespace splat::cli {

// InputError naming the file when it cannot be written.
void write_json_file(const std::filesystem::path& file, const nlohmann::json& json);

// The parsed file, or nothing when it does not exist; InputError naming it when malformed.
std::optional<nlohmann::json> read_json_if_present(const std::filesystem::path& file);

}  // namespace splat::cli
