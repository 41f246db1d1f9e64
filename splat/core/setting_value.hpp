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

// `value` as a T, or ArgumentError `"key" must be …`.
template <class T>
T read_setting(const nlohmann::json& value, const std::string& key, const SettingRange& range) {
  if constexpr (std::is_same_v<T, bool>) {
    if (!value.is_boolean()) throw ArgumentError("\"" + key + "\" must be true or false");
    return value.get<bool>();
  } else {
    static_assert(std::is_arithmetic_v<T>);
    constexpr bool whole = std::is_integral_v<T>;
    const std::string wanted = std::string(whole ? "a whole number" : "a number") + " from " +
                               format_setting_number(range.lo) + " to " +
                               format_setting_number(range.hi);
    if (!value.is_number()) throw ArgumentError("\"" + key + "\" must be " + wanted + ", not " + value.dump());
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < range.lo || v > range.hi || (whole && v != std::floor(v)))
      throw ArgumentError("\"" + key + "\" must be " + wanted + " (got " + value.dump() + ")");
    return static_cast<T>(v);
  }
}

}  // namespace splat
