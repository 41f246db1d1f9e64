#pragma once
// Trainer settings from a JSON file (splat-train --config, splat-eval --splat-config and
// --nerf-config): the fields present override `config`.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"

namespace splat::cli {

// The file's JSON; InputError naming the file when it cannot be opened or is not JSON.
inline nlohmann::json read_config_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, "cannot open the config file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed JSON: ") + e.what());
  }
}

// `json` (read from `file`) over `config`; InputError naming the file for an unknown key or a
// bad value (from_json's ArgumentError).
template <class Config>
void apply_config_json(const std::filesystem::path& file, const nlohmann::json& json, Config& config) {
  try {
    from_json(json, config);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed JSON: ") + e.what());
  } catch (const ArgumentError& e) {
    throw InputError(file, e.what());
  }
}

template <class Config>
void read_config_file(const std::filesystem::path& file, Config& config) {
  apply_config_json(file, read_config_json(file), config);
}

}  // namespace splat::cli
