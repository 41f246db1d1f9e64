#pragma once
// Trainer settings from a JSON file (splat-train --config, splat-eval --splat-config and
// --nerf-config): the fields present override `config`.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"

namespace splat::cli {

// InputError naming the file when it cannot be opened, is not JSON, or holds an unknown key
// or bad value (from_json's ArgumentError).
template <class Config>
void read_config_file(const std::filesystem::path& file, Config& config) {
  std::ifstream in(file);
  if (!in) throw InputError(file, "cannot open the config file");
  try {
    from_json(nlohmann::json::parse(in), config);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed JSON: ") + e.what());
  } catch (const ArgumentError& e) {
    throw InputError(file, e.what());
  }
}

}  // namespace splat::cli
