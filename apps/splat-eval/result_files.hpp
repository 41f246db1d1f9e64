#pragma once
// splat-eval's JSON result files: written through a temporary name (never half-written),
// read back by the charts and the report.
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace splat::cli {

// InputError naming the file when it cannot be written.
void write_json_file(const std::filesystem::path& file, const nlohmann::json& json);

// The parsed file, or nothing when it does not exist; InputError naming it when malformed.
std::optional<nlohmann::json> read_json_if_present(const std::filesystem::path& file);

// Runs `use` on the file's JSON when the file exists. A result file whose content is not what
// splat-eval writes (a key missing, a value of the wrong type: hand-edited, or from another
// tool) becomes one InputError naming the file and the problem, not the JSON library's raw
// message.
void with_result_file(const std::filesystem::path& file, const std::function<void(const nlohmann::json&)>& use);

// How the charts and the report name the method of a run (a method of results.json, a
// stability run, sweep.json): "NeRF", "splat (compact)", "splat (official)"; files from before
// the density strategies name no strategy, and their "splat" stays "splat".
std::string method_label(const nlohmann::json& run);

}  // namespace splat::cli
