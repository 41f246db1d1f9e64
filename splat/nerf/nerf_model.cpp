#include "splat/nerf/nerf_model.hpp"

#include <algorithm>

#include "splat/core/error.hpp"
#include "splat/core/settings_table.hpp"

namespace splat {

float NerfSettings::coarse_step() const {
  const int in_box = unbounded ? std::max(1, coarse_samples / 2) : std::max(1, coarse_samples);
  return glm::length(box.hi - box.lo) / float(in_box);
}

void validate(const NerfSettings& s, const std::string& path) {
  if (!(s.box.lo.x < s.box.hi.x && s.box.lo.y < s.box.hi.y && s.box.lo.z < s.box.hi.z))
    throw ArgumentError("\"" + path + ".box_min\" must be below \"" + path + ".box_max\" on every axis");
  check_setting_ranges(s, path);
  validate(s.coarse, path + ".coarse");
  validate(s.fine, path + ".fine");
}

}  // namespace splat
