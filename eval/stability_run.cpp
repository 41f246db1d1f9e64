#include <cstdio>
#include <functional>
#include <tbb/info.h>

#include "eval_methods.hpp"
#include "eval_modes.hpp"
#include "method_run.hpp"
#include "progress_reporter.hpp"
#include "splat/eval/stability_conditions.hpp"

namespace splat::cli {

namespace {

// One condition: a changed copy of the dataset, or the reason it does not apply here.
struct Condition {
  std::string id;    // folder name under stability/
  std::string name;  // as the table shows it
  std::string kind;  // baseline | views | pose noise | initialisation
  std::string skipped;
  std::function<Dataset()> make;
};

std::string format(const char* pattern, double a, double b = 0) {
  char text[120];
  std::snprintf(text, sizeof(text), pattern, a, b);
  return text;
}

std::vector<Condition> conditions_for(const EvalCommandOptions& options, const Dataset& dataset) {
  const int views = int(dataset.train.size());
  std::vector<Condition> list;
  list.push_back({"baseline", "all " + std::to_string(views) + " views", "baseline", "", [&] { return dataset; }});
  for (int n : options.stability_views) {
    Condition c{"views_" + std::to_string(n), std::to_string(n) + " views", "views", "", {}};
    if (n >= views)
      c.skipped = "the dataset has only " + std::to_string(views) + " training views";
    else
      c.make = [&dataset, n] { return with_training_views(dataset, n); };
    list.push_back(c);
  }
  for (const PoseNoiseLevel& level : options.pose_noise_levels) {
    list.push_back({format("pose_noise_%gdeg_%gpct", level.rotation_deg, 100 * level.translation_fraction),
                    format("poses %g° / %g%%", level.rotation_deg, 100 * level.translation_fraction),
                    "pose noise", "",
                    // The seed of the splat settings (the presets share it), whichever methods run.
                    [&dataset, level, seed = method_request(options, "splat", {}).splat_config.seed] {
                      return with_pose_noise(dataset, level.rotation_deg, level.translation_fraction, seed + 1);
                    }});
  }
  Condition random{"random_init", "random initialisation", "initialisation", "", {}};
  if (dataset.points)
    random.make = [&dataset] { return without_point_cloud(dataset); };
  else
    random.skipped = "the dataset has no point cloud: its baseline already starts from random points";
  list.push_back(random);
  return list;
}

}  // namespace

void run_stability(const EvalCommandOptions& options, const Dataset& dataset) {
  const std::vector<std::string> methods = methods_to_run(options);
  const std::vector<Condition> conditions = conditions_for(options, dataset);
  int runnable = 0;
  for (const Condition& c : conditions) runnable += c.skipped.empty() ? 1 : 0;
  EvalProgress progress(options.quiet, int(methods.size()) * runnable, options.max_seconds, 1);
  std::string method_list;
  for (const std::string& method : methods) method_list += (method_list.empty() ? "" : ", ") + method;
  progress.message("stability on " + options.data.string() + ": " + std::to_string(runnable) + " conditions, " +
                   method_list + ", " + format_duration(options.max_seconds) + " each");

  const VerdictRules rules;
  const double background_psnr = background_only_psnr(dataset.test, options.dataset.background);
  nlohmann::json table = nlohmann::json::array();
  std::vector<std::optional<double>> baseline_psnr(methods.size());  // [method]
  int run_index = 0;
  for (const Condition& condition : conditions) {
    nlohmann::json entry = {{"id", condition.id}, {"name", condition.name}, {"kind", condition.kind}};
    if (!condition.skipped.empty()) {
      entry["skipped"] = condition.skipped;
      progress.message("skipping " + condition.name + ": " + condition.skipped);
      table.push_back(entry);
      continue;
    }
    const Dataset changed = condition.make();
    entry["train_views"] = changed.train.size();
    entry["runs"] = nlohmann::json::array();
    for (std::size_t m = 0; m < methods.size(); ++m) {
      progress.start_run(run_index++, condition.name + " / " + methods[m]);
      MethodRun run = run_method(method_request(options, methods[m], options.out / "stability" / condition.id / methods[m]),
                                 changed, progress);
      nlohmann::json& r = run.json;
      r.erase("config");
      const double psnr = run.diverged ? 0.0 : r["final"]["psnr"].get<double>();
      if (condition.kind == "baseline" && !run.diverged) baseline_psnr[m] = psnr;
      const std::optional<double> reference =
          condition.kind == "baseline" ? std::nullopt : baseline_psnr[m];
      r["verdict"] = verdict_name(classify_run(run.diverged, psnr, background_psnr, reference, rules));
      progress.message("[" + condition.name + " / " + methods[m] + "] verdict: " + r["verdict"].get<std::string>());
      entry["runs"].push_back(r);
    }
    table.push_back(entry);
  }

  nlohmann::json j;
  j["data"] = options.data.string();
  j["budget_seconds"] = options.max_seconds;
  j["threads"] = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  j["train_views"] = dataset.train.size();
  j["test_views"] = dataset.test.size();
  j["background_only_psnr"] = background_psnr;
  j["collapse_psnr"] = background_psnr + rules.collapse_margin_db;
  j["rules"] = {
      {"diverged", "training stopped on a non-finite loss or parameter (the iteration is recorded)"},
      {"collapsed", format("test PSNR <= the background alone (%.2f dB) + %g dB", background_psnr,
                           rules.collapse_margin_db)},
      {"degraded", format("test PSNR more than %g dB below the same method's baseline", rules.degrade_db)},
      {"ok", "none of the above"}};
  j["conditions"] = table;
  write_json_file(options.out / "stability.json", j);
}

}  // namespace splat::cli
