#pragma once
// What a resumed run trains with (docs/DESIGN.md §4.6). The checkpoint fixes the run's
// settings: a resumed run continues the run it was written by, not another. The limits and
// reporting intervals are the exception (iterations, max_seconds, test_interval,
// checkpoint_interval): given again, they replace the checkpoint's, so a run can be extended,
// and are recorded in config.json. Any other setting given with a value other than the
// checkpoint's is refused, naming the option; given with the same value it is no change.
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace splat {

// The settings this run's command line set, by config key ("strategy", "seed", "model"), each
// with the option that set it, for messages ("--strategy", "--config run.json").
using GivenSettings = std::map<std::string, std::string>;

// The settings to resume with: `checkpoint`'s, with the given limits and intervals taken from
// `requested` (this run's settings as JSON). ArgumentError when a given setting differs.
nlohmann::json resumed_settings(const nlohmann::json& checkpoint, const nlohmann::json& requested,
                                const GivenSettings& given);

}  // namespace splat
