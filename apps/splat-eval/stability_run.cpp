#include <algorithm>
#include <cstdio>
#include <functional>
#include <map>
#include <tbb/info.h>

#include "apps/splat-eval/eval_methods.hpp"
#include "apps/splat-eval/eval_modes.hpp"
#include "apps/splat-eval/method_run.hpp"
#include "apps/common/progress_reporter.hpp"
#include "splat/eval/stability_conditions.hpp"

namespace splat::cli {

namespace {

// One condition: a changed copy of the dataset, or the reason it does not apply here.
struct Condition {
  std::string id;    // folder name under stability/
  std::string name;  // as the table shows it
  std::string kind;  // baseline | views | pose noise | initialisation, "+ refinement" for refine
  std::string skipped;
  std::function<Dataset()> make;
  bool refine_poses = false;  // splat methods only, with --refine-poses
};

bool wanted(const EvalCommandOptions& options, const std::string& kind) {
  return options.stability_kinds.empty() ||
         std::find(options.stability_kinds.begin(), options.stability_kinds.end(), kind) !=
             options.stability_kinds.end();
}

// The condition trained again with pose refinement (kind "refinement").
Condition refined(Condition c) {
  c.id += "_refine";
  c.name += " + refinement";
  c.kind += " + refinement";
  c.refine_poses = true;
  return c;
}

template <class... Numbers>
std::string format(const char* pattern, Numbers... numbers) {
  char text[256];
  std::snprintf(text, sizeof(text), pattern, numbers...);
  return text;
}

std::vector<Condition> conditions_for(const EvalCommandOptions& options, const Dataset& dataset) {
  const int views = int(dataset.train.size());
  std::vector<Condition> list;
  const bool refinement = wanted(options, "refinement");
  // Photographs with structure from motion (a point cloud) are a real capture: its baseline
  // row is the question whether training holds its best on such data.
  const std::string all_views = "all " + std::to_string(views) + " views";
  const Condition all{"baseline", dataset.points ? "real capture, " + all_views : all_views, "baseline", "",
                      [&] { return dataset; }};
  if (wanted(options, "baseline")) list.push_back(all);
  if (refinement) list.push_back(refined(all));
  for (int n : wanted(options, "views") ? options.stability_views : std::vector<int>{}) {
    Condition c{"views_" + std::to_string(n), std::to_string(n) + " views", "views", "", {}};
    if (n >= views)
      c.skipped = "the dataset has only " + std::to_string(views) + " training views";
    else
      c.make = [&dataset, n] { return with_training_views(dataset, n); };
    list.push_back(c);
  }
  for (const PoseNoiseLevel& level : options.pose_noise_levels) {
    const Condition noisy{
        format("pose_noise_%gdeg_%gpct", level.rotation_deg, 100 * level.translation_fraction),
        format("poses %g° / %g%%", level.rotation_deg, 100 * level.translation_fraction), "pose noise", "",
        // The seed of the splat settings (the presets share it), whichever methods run.
        [&dataset, level, seed = method_request(options, "splat", {}).splat_config.seed] {
          return with_pose_noise(dataset, level.rotation_deg, level.translation_fraction, seed + 1);
        }};
    if (wanted(options, "pose-noise")) list.push_back(noisy);
    if (refinement) list.push_back(refined(noisy));
  }
  Condition random{"random_init", "random initialisation", "initialisation", "", {}};
  if (dataset.points)
    random.make = [&dataset] { return without_point_cloud(dataset); };
  else
    random.skipped = "the dataset has no point cloud: its baseline already starts from random points";
  if (wanted(options, "random-init")) list.push_back(random);
  return list;
}

// The methods a condition trains: pose refinement is the splat methods' alone.
std::vector<std::string> methods_for(const Condition& condition, const std::vector<std::string>& methods) {
  std::vector<std::string> chosen;
  for (const std::string& method : methods)
    if (!condition.refine_poses || splat_strategy(method)) chosen.push_back(method);
  return chosen;
}

}  // namespace

void run_stability(const EvalCommandOptions& options, const Dataset& dataset) {
  const std::vector<std::string> methods = methods_to_run(options);
  std::vector<Condition> conditions = conditions_for(options, dataset);
  for (Condition& c : conditions)
    if (c.skipped.empty() && methods_for(c, methods).empty())
      c.skipped = "pose refinement is the splat methods' alone, and none of them runs";
  int runs = 0;
  for (const Condition& c : conditions) runs += c.skipped.empty() ? int(methods_for(c, methods).size()) : 0;
  EvalProgress progress(options.quiet, runs, options.max_seconds, 0, int(dataset.test.size()));
  std::string method_list;
  for (const std::string& method : methods) method_list += (method_list.empty() ? "" : ", ") + method;
  progress.message("stability on " + options.data.string() + ": " + std::to_string(runs) + " runs of " +
                   method_list + ", " + format_duration(options.max_seconds) + " each");

  const VerdictRules rules;
  std::vector<Camera> true_training_cameras;  // against which refinement's pose error is measured
  for (const DatasetView& view : dataset.train) true_training_cameras.push_back(view.camera);
  const double background_psnr = background_only_psnr(dataset.test, options.dataset.background);
  nlohmann::json table = nlohmann::json::array();
  std::map<std::string, double> baseline_psnr;  // by method
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
    for (const std::string& method : methods_for(condition, methods)) {
      progress.start_run(run_index++, condition.name + " / " + method);
      MethodRunRequest request = method_request(options, method, options.out / "stability" / condition.id / method);
      request.splat_config.refine_poses = request.splat_config.refine_poses || condition.refine_poses;
      if (changed.train.size() == dataset.train.size()) request.true_training_cameras = &true_training_cameras;
      MethodRun run = run_method(request, changed, progress);
      nlohmann::json& r = run.json;
      r.erase("config");
      const double psnr = run.diverged ? 0.0 : r["final"]["psnr"].get<double>();
      if (condition.kind == "baseline" && !run.diverged) baseline_psnr[method] = psnr;
      std::optional<double> reference;
      if (condition.kind != "baseline" && baseline_psnr.count(method)) reference = baseline_psnr[method];
      r["verdict"] = verdict_name(classify_run(run.diverged, psnr, background_psnr, reference, rules));
      if (r.contains("drop_from_best")) r["holds_best"] = r["drop_from_best"].get<double>() <= rules.hold_best_db;
      progress.message("[" + condition.name + " / " + method + "] verdict: " + r["verdict"].get<std::string>());
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
  j["real_capture"] = dataset.points.has_value();
  j["background_only_psnr"] = background_psnr;
  j["collapse_psnr"] = background_psnr + rules.collapse_margin_db;
  j["failure_psnr"] = rules.failure_psnr(background_psnr);
  j["rules"] = {
      {"diverged", "training stopped on a non-finite loss or parameter (the iteration is recorded)"},
      {"collapsed", format("test PSNR <= the background alone (%.2f dB) + %g dB", background_psnr,
                           rules.collapse_margin_db)},
      {"failed", format("test PSNR below the absolute floor of %.2f dB, the higher of the background alone + %g dB "
                        "and %g dB, whatever the method's baseline (the baseline itself can fail)",
                        rules.failure_psnr(background_psnr), rules.failure_margin_db, rules.failure_floor_db)},
      {"degraded", format("test PSNR more than %g dB below the same method's baseline", rules.degrade_db)},
      {"ok", "none of the above"},
      {"holds_best", format("final test PSNR at most %g dB below the run's best test point", rules.hold_best_db)}};
  j["conditions"] = table;
  write_json_file(options.out / "stability.json", j);
}

}  // namespace splat::cli
