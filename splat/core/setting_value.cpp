#include "splat/core/setting_value.hpp"

#include <cstdio>

namespace splat {

std::string format_setting_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

std::string setting_range_text(bool whole, const SettingRange& range) {
  return std::string(whole ? "a whole number" : "a number") + " from " + format_setting_number(range.lo) + " to " +
         format_setting_number(range.hi);
}

}  // namespace splat
