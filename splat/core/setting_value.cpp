#include "splat/core/setting_value.hpp"

#include <cstdio>

namespace splat {

std::string format_setting_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

}  // namespace splat
