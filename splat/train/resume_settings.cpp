#include "splat/train/resume_settings.hpp"

#include <algorithm>
#include <array>

#include "splat/core/error.hpp"

namespace splat {

namespace {

// The settings a resumed run may change: how long it runs and how often it reports.
constexpr std::array<const char*, 4> kChangeableOnResume = {"iterations", "max_seconds", "test_interval",
                                                           "checkpoint_interval"};

bool changeable_on_resume(const std::string& key) {
  return std::find(kChangeableOnResume.begin(), kChangeableOnResume.end(), key) != kChangeableOnResume.end();
}

}  // namespace

nlohmann::json resumed_settings(const nlohmann::json& checkpoint, const nlohmann::json& requested,
                                const GivenSettings& given) {
  nlohmann::json settings = checkpoint;
  for (const auto& [key, option] : given) {
    const auto wanted = requested.find(key);
    if (wanted == requested.end()) continue;
    if (changeable_on_resume(key)) {
      settings[key] = *wanted;
      continue;
    }
    const auto kept = checkpoint.find(key);
    if (kept != checkpoint.end() && *kept != *wanted)
      throw ArgumentError(option + " sets \"" + key + "\" to " + wanted->dump() + ", but the checkpoint's run has " +
                          kept->dump() + ": a resumed run keeps its settings (leave it out, or train afresh "
                          "into another --out); only the limits and intervals change on --resume");
  }
  return settings;
}

}  // namespace splat
