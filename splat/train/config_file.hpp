#pragma once
// Trainer settings from a JSON file (splat-train --config, splat-eval --splat-config and
// --nerf-config): the fields present override `config`.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"
#include "splat/core/json_file.hpp"

namespace splat {

// The file's JSON; InputError naming the file when it cannot be opened or is not JSON.
inline nlohmann::json read_config_json(const std::filesystem::path& file) {
  return read_json_file(file, "config file");
}

// `json` (read from `file`) over `config`; InputError naming the file for an unknown key or a
// bad value (from_json's ArgumentError).
template <class Config>
void apply_config_json(const std::filesystem::path& file, const nlohmann::json& json, Config& config) {
  try {
    from_json(json, config);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, json_error_text(e));
  } catch (const ArgumentError& e) {
    throw InputError(file, e.what());
  }
}

template <class Config>
void read_config_file(const std::filesystem::path& file, Config& config) {
  apply_config_json(file, read_config_json(file), config);
}

}  // namespace splat
