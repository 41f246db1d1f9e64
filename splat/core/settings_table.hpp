#pragma once
// The settings of a config struct described once, in a table that every job walks: writing
// the struct as JSON (config.json, checkpoint and .nerf headers), reading JSON over it, and
// checking values set in code (the command line, presets) against the same ranges. Both
// trainers' configs and the NeRF's model settings use it (docs/DESIGN.md §4.7).
//
// A struct takes part with a function template found by argument-dependent lookup (so in the
// struct's own namespace, not an unnamed one), one line a setting, in the order they are read:
//
//   template <class Table>
//   void describe_settings(Table& t, MyConfig& c) {
//     t.number("iterations", c.iterations, {1, kMaxTrainingIterations});
//     t.flag("refine_poses", c.refine_poses);
//     t.choice("activation", c.activation, {{"relu", Activation::kRelu}, {"softplus", ...}});
//     t.triple("background", c.background, {0, 1});  // a JSON array of 3 numbers
//     t.section("model", c.model);                    // a nested object with a table of its own
//     t.constant("method", "nerf");                   // always written; read, it must match
//   }
//
// The struct's member initialisers are its defaults, and its `validate` checks the ranges
// (check_setting_ranges) and whatever relates one setting to another.
#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"
#include "splat/core/setting_value.hpp"

namespace splat {

// How read_settings treats the keys of one JSON object.
struct SettingsReading {
  // The object's name in messages: keys are named "path.key" ("model.near"), and a value that
  // is not an object is "<path> must be a JSON object" (`what` where the path is empty).
  std::string path = {};
  std::string what = "the config";
  // The first words of the message for a key the table does not know: `unknown setting "k"`.
  std::string unknown = "unknown setting";
  // false: a key that is absent keeps the struct's value (a config file gives any subset).
  // true: an absent key is an error ("is missing"), unless it is in `optional` (keys that
  // older files lack: the value the struct holds before reading stays).
  bool every_key = false;
  std::vector<std::string> optional = {};
  // Keys accepted but not read (older spellings, or values the file writes beside the
  // settings): the caller deals with them.
  std::vector<std::string> ignored = {};
};

namespace settings_detail {

inline std::string key_path(const std::string& path, const char* name) {
  return path.empty() ? std::string(name) : path + "." + name;
}

// `"a" or "b"`, `"a", "b" or "c"`.
template <class Names>
std::string alternatives(const Names& names) {
  std::string text;
  std::size_t i = 0;
  for (const auto& name : names) {
    if (i > 0) text += i + 1 == std::size(names) ? " or " : ", ";
    text += '"';
    text += name;
    text += '"';
    ++i;
  }
  return text;
}

template <class T>
std::vector<const char*> names_of(std::initializer_list<std::pair<const char*, T>> options) {
  std::vector<const char*> names;
  for (const auto& option : options) names.push_back(option.first);
  return names;
}

[[noreturn]] inline void choice_error(const std::string& key, const std::string& wanted, const std::string& got) {
  throw ArgumentError("\"" + key + "\" must be " + wanted + " (got " + got + ")");
}

// The table's keys, in order.
struct Names {
  std::vector<std::string> keys;
  template <class T>
  void number(const char* name, T&, const SettingRange&) { keys.push_back(name); }
  void flag(const char* name, bool&) { keys.push_back(name); }
  template <class T, class Options>
  void choice(const char* name, T&, const Options&) { keys.push_back(name); }
  template <class T>
  void choice(const char* name, T&, std::initializer_list<std::pair<const char*, T>>) { keys.push_back(name); }
  template <class V>
  void triple(const char* name, V&, const SettingRange&) { keys.push_back(name); }
  template <class S, class Read>
  void section(const char* name, S&, Read) { keys.push_back(name); }
  template <class S>
  void section(const char* name, S&) { keys.push_back(name); }
  void constant(const char* name, const char*) { keys.push_back(name); }
};

}  // namespace settings_detail

template <class Config>
std::vector<std::string> setting_keys(Config config) {
  settings_detail::Names names;
  describe_settings(names, config);
  return names.keys;
}

// Every setting of `config` as one JSON object (sections as nested objects).
template <class Config>
nlohmann::json settings_json(Config config);

// A struct with a table read from `json` as `how` says, then validate(config, how.path): how a
// section is read unless its table line names another way.
template <class Config>
Config settings_from_json(const nlohmann::json& json, const SettingsReading& how);

namespace settings_detail {

struct Writer {
  nlohmann::json json = nlohmann::json::object();
  template <class T>
  void number(const char* name, T& value, const SettingRange&) { json[name] = value; }
  void flag(const char* name, bool& value) { json[name] = value; }
  template <std::size_t N>
  void choice(const char* name, std::string& value, const char* const (&)[N]) { json[name] = value; }
  template <class T>
  void choice(const char* name, T& value, std::initializer_list<std::pair<const char*, T>> options) {
    for (const auto& [text, option] : options)
      if (option == value) json[name] = text;
  }
  template <class V>
  void triple(const char* name, V& v, const SettingRange&) { json[name] = {v[0], v[1], v[2]}; }
  template <class S, class Read>
  void section(const char* name, S& value, Read) { json[name] = settings_json(value); }
  template <class S>
  void section(const char* name, S& value) { json[name] = settings_json(value); }
  void constant(const char* name, const char* value) { json[name] = value; }
};

struct Reader {
  const nlohmann::json& json;
  const SettingsReading& how;

  // The value of `name`, or null when it is absent (an error where every key is needed).
  const nlohmann::json* find(const char* name) const {
    const auto it = json.find(name);
    if (it != json.end()) return &*it;
    if (how.every_key && std::find(how.optional.begin(), how.optional.end(), name) == how.optional.end())
      throw ArgumentError("\"" + key_path(how.path, name) + "\" is missing");
    return nullptr;
  }
  template <class T>
  void number(const char* name, T& value, const SettingRange& range) {
    if (const auto* v = find(name)) value = read_setting<T>(*v, key_path(how.path, name), range);
  }
  void flag(const char* name, bool& value) {
    if (const auto* v = find(name)) value = read_setting<bool>(*v, key_path(how.path, name), {});
  }
  template <std::size_t N>
  void choice(const char* name, std::string& value, const char* const (&names)[N]) {
    const auto* v = find(name);
    if (!v) return;
    if (!v->is_string() || std::none_of(std::begin(names), std::end(names), [&](const char* n) { return *v == n; }))
      choice_error(key_path(how.path, name), alternatives(names), v->dump());
    value = v->get<std::string>();
  }
  template <class T>
  void choice(const char* name, T& value, std::initializer_list<std::pair<const char*, T>> options) {
    const auto* v = find(name);
    if (!v) return;
    for (const auto& [text, option] : options)
      if (v->is_string() && *v == text) {
        value = option;
        return;
      }
    choice_error(key_path(how.path, name), alternatives(names_of(options)), v->dump());
  }
  template <class V>
  void triple(const char* name, V& v, const SettingRange& range) {
    const auto* value = find(name);
    if (!value) return;
    const std::string key = key_path(how.path, name);
    if (!value->is_array() || value->size() != 3) throw ArgumentError("\"" + key + "\" needs 3 numbers");
    for (std::size_t i = 0; i < 3; ++i) v[int(i)] = read_setting<float>((*value)[i], key, range);
  }
  // A section is read whole by `read` (S read(const json&, const SettingsReading&)), every
  // key needed; in a config file, where keys may be left out, its keys are first merged one
  // by one over the current settings.
  template <class S, class Read>
  void section(const char* name, S& value, Read read) {
    const auto* v = find(name);
    if (!v) return;
    const std::string path = key_path(how.path, name);
    const SettingsReading whole{.path = path, .what = path, .unknown = how.unknown, .every_key = true};
    if (how.every_key) {
      value = read(*v, whole);
    } else {
      nlohmann::json merged = settings_json(value);
      merged.merge_patch(*v);
      value = read(merged, whole);
    }
  }
  template <class S>
  void section(const char* name, S& value) {
    section(name, value, [](const nlohmann::json& j, const SettingsReading& whole) { return settings_from_json<S>(j, whole); });
  }
  void constant(const char* name, const char* expected) {
    const auto* v = find(name);
    if (v && !(v->is_string() && *v == expected))
      choice_error(key_path(how.path, name), alternatives(std::vector<const char*>{expected}), v->dump());
  }
};

struct RangeCheck {
  const std::string& path;
  template <class T>
  void number(const char* name, T& value, const SettingRange& range) {
    check_setting_value(value, key_path(path, name), range);
  }
  void flag(const char*, bool&) {}
  template <std::size_t N>
  void choice(const char* name, std::string& value, const char* const (&names)[N]) {
    if (std::none_of(std::begin(names), std::end(names), [&](const char* n) { return value == n; }))
      choice_error(key_path(path, name), alternatives(names), "\"" + value + "\"");
  }
  template <class T>
  void choice(const char* name, T& value, std::initializer_list<std::pair<const char*, T>> options) {
    if (std::none_of(options.begin(), options.end(), [&](const auto& o) { return o.second == value; }))
      choice_error(key_path(path, name), alternatives(names_of(options)), "another value");
  }
  template <class V>
  void triple(const char* name, V& v, const SettingRange& range) {
    for (int i = 0; i < 3; ++i) check_setting_value(v[i], key_path(path, name), range);
  }
  // A section's own validate checks it.
  template <class S, class Read>
  void section(const char*, S&, Read) {}
  template <class S>
  void section(const char*, S&) {}
  void constant(const char*, const char*) {}
};

}  // namespace settings_detail

template <class Config>
nlohmann::json settings_json(Config config) {
  settings_detail::Writer writer;
  describe_settings(writer, config);
  return std::move(writer.json);
}

// Reads the keys of `json` over `config` as `how` says, each checked against its range as it
// is read (ArgumentError naming the key); a key the table does not know is an error before
// anything is read.
template <class Config>
void read_settings(const nlohmann::json& json, Config& config, const SettingsReading& how) {
  if (!json.is_object()) throw ArgumentError((how.path.empty() ? how.what : how.path) + " must be a JSON object");
  const std::vector<std::string> keys = setting_keys(config);
  for (const auto& item : json.items())
    if (std::find(keys.begin(), keys.end(), item.key()) == keys.end() &&
        std::find(how.ignored.begin(), how.ignored.end(), item.key()) == how.ignored.end())
      throw ArgumentError(how.unknown + " \"" + settings_detail::key_path(how.path, item.key().c_str()) + "\"");
  settings_detail::Reader reader{json, how};
  describe_settings(reader, config);
}

// Throws ArgumentError naming the first setting of `config` outside its range (sections are
// left to their own validate).
template <class Config>
void check_setting_ranges(Config config, const std::string& path = "") {
  settings_detail::RangeCheck check{path};
  describe_settings(check, config);
}

template <class Config>
Config settings_from_json(const nlohmann::json& json, const SettingsReading& how) {
  Config config;
  read_settings(json, config, how);
  validate(config, how.path);
  return config;
}

// `config` after validate(config): for a constructor's member initialisers.
template <class Config>
const Config& validated(const Config& config) {
  validate(config);
  return config;
}

}  // namespace splat
