#pragma once
// One setting of a config file, checked as it is read: a number must be finite, within its
// stated range and, for a whole-number setting, whole; a flag must be true or false. A value
// no run can use (a negative rate, 3.5 or 1e30 iterations, a zero interval) is then an error
// naming the key when the file is read, not a crash, a hang or a huge allocation later.
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "splat/core/error.hpp"

namespace splat {

// A closed interval [lo, hi] of allowed values.
struct SettingRange {
  double lo = -std::numeric_limits<double>::max();
  double hi = std::numeric_limits<double>::max();
};

std::string format_setting_number(double value);

// "a whole number from LO to HI" or "a number from LO to HI".
std::string setting_range_text(bool whole, const SettingRange& range);

// `value` as a T, or ArgumentError `"key" must be …`.
template <class T>
T read_setting(const nlohmann::json& value, const std::string& key, const SettingRange& range) {
  if constexpr (std::is_same_v<T, bool>) {
    if (!value.is_boolean()) throw ArgumentError("\"" + key + "\" must be true or false");
    return value.get<bool>();
  } else {
    static_assert(std::is_arithmetic_v<T>);
    constexpr bool whole = std::is_integral_v<T>;
    const std::string wanted = setting_range_text(whole, range);
    if (!value.is_number()) throw ArgumentError("\"" + key + "\" must be " + wanted + ", not " + value.dump());
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < range.lo || v > range.hi || (whole && v != std::floor(v)))
      throw ArgumentError("\"" + key + "\" must be " + wanted + " (got " + value.dump() + ")");
    return static_cast<T>(v);
  }
}

// The same check on a value already in a struct (set by the command line or by code):
// ArgumentError `"key" must be … (got V)` when it is outside `range` or not finite.
template <class T>
void check_setting_value(T value, const std::string& key, const SettingRange& range) {
  static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>);
  const double v = double(value);
  if (!std::isfinite(v) || v < range.lo || v > range.hi)
    throw ArgumentError("\"" + key + "\" must be " + setting_range_text(std::is_integral_v<T>, range) + " (got " +
                        format_setting_number(v) + ")");
}

}  // namespace splat
