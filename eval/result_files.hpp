#pragma once
// splat-eval's JSON result files: written through a temporary name (never half-written),
// read back by the charts and the report.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace splat::cli {

// InputError naming the file when it cannot be written.
void write_json_file(const std::filesystem::path& file, const nlohmann::json& json);

// The parsed file, or nothing when it does not exist; InputError naming it when malformed.
std::optional<nlohmann::json> read_json_if_present(const std::filesystem::path& file);

// How the charts and the report name the method of a run (a method of results.json, a
// stability run, sweep.json): "NeRF", "splat (compact)", "splat (official)"; files from before
// the density strategies name no strategy, and their "splat" stays "splat".
std::string method_label(const nlohmann::json& run);

}  // namespace splat::cli
