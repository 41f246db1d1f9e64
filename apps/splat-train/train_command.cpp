#include "apps/splat-train/train_command.hpp"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <tbb/info.h>
#include <unistd.h>

#include "apps/common/thread_limit.hpp"
#include "apps/common/progress_reporter.hpp"
#include "splat/core/atomic_file.hpp"
#include "splat/core/json_file.hpp"
#include "splat/data/image_io.hpp"
#include "splat/eval/quality_levels.hpp"
#include "splat/optim/step_events.hpp"
#include "splat/gaussians/ply_io.hpp"
#include "splat/train/splat_trainer.hpp"
#include "splat/train/trainer_adapter.hpp"
#include "splat/train/training_loop.hpp"

namespace splat::cli {

namespace {

namespace fs = std::filesystem;

constexpr const char* kCheckpointName = "checkpoint.ckpt";
constexpr int kHistoryInterval = 100;  // iterations per history entry

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) { g_interrupted = true; }

std::size_t peak_memory_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return std::size_t(usage.ru_maxrss) * 1024;  // ru_maxrss is in KiB on Linux
}

void write_json(const fs::path& file, const nlohmann::json& json) {
  write_stream_atomically(file, [&](std::ostream& out) { out << json.dump(1) << "\n"; });
}

fs::path checkpoint_file(const fs::path& resume) {
  return fs::is_directory(resume) ? resume / kCheckpointName : resume;
}

// Running means of the per-iteration figures since the last history entry.
struct WindowAverages {
  double loss = 0;
  IterationTimings timings;
  // Over several ranks: bytes sent, and the fractions of the rows drawn in this rank's block
  // and in the batch.
  double exchange_bytes = 0, block_visible = 0, batch_visible = 0;
  int count = 0;
  void add(const StepResult& r) {
    loss += r.loss;
    timings += r.timings;
    const double rows = double(std::max<std::size_t>(1, r.exchange.rows));
    exchange_bytes += double(r.exchange.bytes_sent);
    block_visible += double(r.exchange.block_visible_rows) / rows;
    batch_visible += double(r.exchange.batch_visible_rows) / rows;
    ++count;
  }
};

// Mean milliseconds per stage; the rasterizer's parts only where there are any (splats).
nlohmann::json timings_json(const IterationTimings& t, int count) {
  const double n = std::max(1, count);
  nlohmann::json j;
  for (const auto& [name, field] : IterationTimings::kFields) j[name] = t.*field / n;
  if (t.project + t.bin_sort + t.blend + t.blend_backward + t.project_backward == 0)
    for (const char* part : {"project", "bin_sort", "blend", "blend_backward", "project_backward"}) j.erase(part);
  if (t.exchange == 0) j.erase("exchange");  // one process
  j["total"] = t.total() / n;
  return j;
}

// splat-train's side of the training loop: the history, checkpoints and progress bar.
class TrainingRun final : public TrainingObserver {
 public:
  TrainingRun(const TrainCommandOptions& options, const Dataset& dataset)
      : options_(options), dataset_(dataset), trainer_(make_trainer(options.method, options.config, options.nerf_config, dataset)),
        schedule_(trainer_->schedule()), progress_(isatty(STDOUT_FILENO) && !options.quiet) {
    trainer_->set_process_group(options.group);
  }

  int run();
  void on_step(const StepResult& step, const LoopState& state) override;
  void on_score(const Evaluation& evaluation, double evaluate_seconds, const LoopState& state) override;

 private:
  void write_outputs(const std::string& stopped_by, double train_seconds);
  nlohmann::json metrics(const std::string& stopped_by, double train_seconds, std::size_t model_bytes) const;
  // The test views' PSNR by view name (which views a run loses is what a mean hides).
  nlohmann::json view_psnr_json(const Evaluation& evaluation) const;
  // A test point's scores, added to its history entry.
  void add_test_scores(nlohmann::json& entry, const Evaluation& evaluation) const;
  std::filesystem::path model_path() const { return options_.out / trainer_->model_file_name(); }
  // Where --snapshot-every writes: "snapshot" with the model's extension.
  std::filesystem::path snapshot_path() const {
    return options_.out / ("snapshot" + std::filesystem::path(trainer_->model_file_name()).extension().string());
  }
  // Whether this process writes the outputs: alone, or rank 0 of a data-parallel run.
  bool leads() const { return options_.group == nullptr || options_.group->rank() == 0; }
  // Waits for every rank (a data-parallel run ends together, after rank 0's outputs).
  void finish_together() const {
    if (options_.group) options_.group->any(false);
  }

  const TrainCommandOptions& options_;
  const Dataset& dataset_;
  std::unique_ptr<TrainerAdapter> trainer_;
  RunSchedule schedule_;
  ProgressReporter progress_;
  nlohmann::json history_ = nlohmann::json::array();
  std::optional<Evaluation> last_test_;
  WindowAverages window_;     // since the last history entry
  WindowAverages whole_run_;  // sums over every iteration this process ran
  double resumed_seconds_ = 0;  // training time before this process (when resuming)
  double last_loss_ = 0;        // loss of the last iteration
  double next_snapshot_seconds_ = 0;  // wall time of the next --snapshot-every write
};

void TrainingRun::on_step(const StepResult& step, const LoopState& state) {
  window_.add(step);
  whole_run_.add(step);
  last_loss_ = step.loss;
  const int it = state.iteration;
  const int views = schedule_.views_per_step;
  if (step_reaches_multiple(it, views, kHistoryInterval) || it == schedule_.iterations) {
    history_.push_back({{"iteration", it}, {"seconds", state.train_seconds},
                        {"loss", window_.loss / std::max(1, window_.count)},
                        {"num_gaussians", trainer_->num_gaussians()},
                        {"ms_per_iteration", timings_json(window_.timings, window_.count)}});
    // The resolution warm-up (resolution_schedule.hpp) explains the fast early iterations.
    if (step.resolution_divisor > 1) history_.back()["resolution_divisor"] = step.resolution_divisor;
    window_ = WindowAverages{};
  }
  if (leads() && step_reaches_multiple(it, views, schedule_.checkpoint_interval))
    trainer_->save_checkpoint(options_.out / kCheckpointName);
  if (leads() && options_.snapshot_seconds > 0 && state.wall_seconds >= next_snapshot_seconds_) {
    // The viewer's cameras with the first one ([ ] step through the views trained on).
    if (next_snapshot_seconds_ == 0) write_view_cameras(*trainer_, dataset_, options_.out);
    trainer_->write_model(snapshot_path());
    next_snapshot_seconds_ = state.wall_seconds + options_.snapshot_seconds;
  }
  if (!options_.quiet) {
    ProgressSnapshot s;
    s.iteration = it;
    s.total_iterations = schedule_.iterations;
    s.elapsed_seconds = state.wall_seconds;
    s.max_seconds = schedule_.max_seconds;
    s.iterations_per_second = state.iterations_per_second();
    s.loss = step.loss;
    if (last_test_) s.test_psnr = last_test_->psnr;
    s.model_size = trainer_->model_size();
    progress_.update(s);
  }
}

// The contract wants a loss in every history entry: when the test point gets an entry of its
// own, its loss is the mean since the previous entry.
void TrainingRun::on_score(const Evaluation& evaluation, double, const LoopState& state) {
  last_test_ = evaluation;
  if (history_.empty() || history_.back()["iteration"] != state.iteration) {
    const double recent_loss = window_.count > 0 ? window_.loss / window_.count : last_loss_;
    history_.push_back({{"iteration", state.iteration}, {"seconds", state.train_seconds},
                        {"loss", recent_loss}, {"num_gaussians", trainer_->num_gaussians()}});
  }
  add_test_scores(history_.back(), evaluation);

  char line[160];
  std::snprintf(line, sizeof(line), "[test] iteration %d: PSNR %.3f dB, SSIM %.4f over %d views (%s)",
                state.iteration, evaluation.psnr, evaluation.ssim, evaluation.views,
                trainer_->model_size().c_str());
  if (!options_.quiet) progress_.message(line);
}

int TrainingRun::run() {
  if (options_.resume) {
    const fs::path file = checkpoint_file(*options_.resume);
    trainer_->load_checkpoint(file, options_.given);
    schedule_ = trainer_->schedule();  // the checkpoint's run, with the limits given now
    if (schedule_.iterations < trainer_->iteration())
      throw ArgumentError("--iters " + std::to_string(schedule_.iterations) + " is below the checkpoint's iteration " +
                          std::to_string(trainer_->iteration()) + ": give more, or leave --iters out");
    const fs::path old_metrics = file.parent_path() / "metrics.json";
    if (fs::exists(old_metrics)) {
      // The history before the resume point continues in the new metrics.json: a file that is
      // not what splat-train writes is named, not silently dropped (or half used).
      const nlohmann::json j = read_json_file(old_metrics, "metrics file");
      const auto history = j.find("history");
      const auto seconds = j.find("train_seconds");
      if (!j.is_object() || history == j.end() || !history->is_array() || seconds == j.end() ||
          !seconds->is_number() || !(seconds->get<double>() >= 0) ||
          !std::all_of(history->begin(), history->end(), [](const nlohmann::json& e) { return e.is_object(); }))
        throw InputError(old_metrics, "not the metrics.json splat-train writes (no \"history\" array of entries or "
                                      "no \"train_seconds\"): move it away to resume without the history before "
                                      "the checkpoint");
      history_ = *history;
      resumed_seconds_ = seconds->get<double>();
    }
    if (!options_.quiet)
      progress_.message("resumed from " + file.string() + " at iteration " +
                        std::to_string(trainer_->iteration()));
  }
  // The output folder once every input is known good (the checkpoint too): a refused run
  // leaves nothing behind.
  std::error_code ec;
  fs::create_directories(options_.out, ec);
  if (!fs::is_directory(options_.out)) throw InputError(options_.out, "cannot create the output folder");
  if (leads()) write_json(options_.out / "config.json", trainer_->config_json());

  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  TrainingLoopOptions loop;
  loop.iterations = schedule_.iterations;
  loop.max_seconds = schedule_.max_seconds;
  loop.budget_clock = BudgetClock::kWall;  // --max-seconds: "seconds of wall time"
  loop.interrupt = &g_interrupted;
  // Test point N scores the model before iteration N's densification and opacity reset,
  // i.e. after N − 1 completed iterations (recorded as such), exactly the parameters the
  // official trainer's report at iteration N sees. Scored after them instead, fresh
  // splits and reset opacities would depress every test point that falls on a
  // densification (all multiples of 100 up to 15,000).
  // Rank 0 scores, when there is something to score (--holdout-every 0 leaves no test views).
  loop.score_every_iterations = leads() && !dataset_.test.empty() ? schedule_.test_interval : 0;
  loop.views_per_step = schedule_.views_per_step;
  loop.score_views = &dataset_.test;
  loop.resumed_seconds = resumed_seconds_;
  loop.group = options_.group;
  const TrainingLoopResult result = run_training_loop(*trainer_, loop, *this);
  progress_.finish();
  if (result.diverged) {
    // Keep what was good: the last parameters that passed the finiteness check.
    if (leads()) {
      trainer_->write_last_good_model(model_path());
      nlohmann::json m = metrics("diverged", result.train_seconds, fs::file_size(model_path()));
      m["diverged"] = {{"iteration", result.diverged->iteration}, {"group", result.diverged->group}};
      write_json(options_.out / "metrics.json", m);
    }
    finish_together();
    throw Error(result.diverged->message + "; the last good model is in " + model_path().string());
  }
  const bool interrupted = result.stopped_by == StopReason::kInterrupt;
  if (!leads()) {
    finish_together();
    return interrupted ? 130 : 0;
  }
  if (interrupted) {
    trainer_->save_checkpoint(options_.out / kCheckpointName);
    if (!options_.quiet)
      progress_.message("interrupted at iteration " + std::to_string(trainer_->iteration()) +
                        ": checkpoint saved to " + (options_.out / kCheckpointName).string() +
                        " (continue with --resume " + options_.out.string() + ")");
  }
  write_outputs(stop_reason_name(result.stopped_by), result.train_seconds);
  finish_together();
  return interrupted ? 130 : 0;
}

namespace {

// The test points of the history as quality levels (splat/eval/quality_levels.hpp).
nlohmann::json time_to_psnr(const nlohmann::json& history) {
  std::vector<ScorePoint> scores;
  for (const nlohmann::json& entry : history)
    if (entry.contains("test_psnr") && entry.at("test_psnr").is_number())
      scores.push_back({entry.at("iteration").get<int>(), entry.at("seconds").get<double>(),
                        entry.at("test_psnr").get<double>()});
  nlohmann::json levels = nlohmann::json::array();
  for (const QualityLevel& level : quality_levels(scores))
    levels.push_back({{"psnr", level.psnr}, {"iteration", level.iteration}, {"seconds", level.seconds},
                      {"after_seconds", level.after_seconds}});
  return levels;
}

}  // namespace

nlohmann::json TrainingRun::view_psnr_json(const Evaluation& evaluation) const {
  nlohmann::json by_name = nlohmann::json::object();
  for (std::size_t i = 0; i < evaluation.view_psnr.size() && i < dataset_.test.size(); ++i)
    by_name[dataset_.test[i].name] = evaluation.view_psnr[i];
  return by_name;
}

void TrainingRun::add_test_scores(nlohmann::json& entry, const Evaluation& evaluation) const {
  entry["test_psnr"] = evaluation.psnr;
  entry["test_ssim"] = evaluation.ssim;
  entry["test_view_psnr"] = view_psnr_json(evaluation);
  entry["test_half_fitted_psnr"] = evaluation.half_fitted_psnr;
}

nlohmann::json TrainingRun::metrics(const std::string& stopped_by, double train_seconds,
                                    std::size_t model_bytes) const {
  nlohmann::json m;
  m["method"] = trainer_->method();
  m["iterations"] = trainer_->iteration();
  m["train_seconds"] = train_seconds;
  m["num_gaussians"] = trainer_->num_gaussians();
  m["num_params"] = trainer_->num_params();
  m["model_bytes"] = model_bytes;
  if (last_test_) {
    m["test"] = {{"psnr", last_test_->psnr}, {"ssim", last_test_->ssim}, {"views", last_test_->views}};
    m["test"]["view_psnr"] = view_psnr_json(*last_test_);
    m["test"]["half_fitted_psnr"] = last_test_->half_fitted_psnr;
  }
  m["history"] = history_;
  m["time_to_psnr"] = time_to_psnr(history_);
  m["stopped_by"] = stopped_by;
  m["ms_per_iteration"] = timings_json(whole_run_.timings, whole_run_.count);
  m["peak_memory_bytes"] = peak_memory_bytes();
  m["threads"] = options_.threads > 0 ? options_.threads : tbb::info::default_concurrency();
  m["ranks"] = options_.group ? options_.group->size() : 1;
  if (whole_run_.exchange_bytes > 0) {  // several ranks: rank 0's means per step
    const double steps = std::max(1, whole_run_.count);
    m["exchange"] = {{"megabytes_sent", whole_run_.exchange_bytes / steps / 1e6},
                     {"rows_drawn_in_block", whole_run_.block_visible / steps},
                     {"rows_drawn_in_batch", whole_run_.batch_visible / steps}};
  }
  trainer_->add_metrics(m);
  m["data"] = options_.data.string();
  m["train_views"] = dataset_.train.size();
  return m;
}

void TrainingRun::write_outputs(const std::string& stopped_by, double train_seconds) {
  if (history_.empty() || history_.back()["iteration"] != trainer_->iteration())
    history_.push_back({{"iteration", trainer_->iteration()}, {"seconds", train_seconds},
                        {"loss", last_loss_}, {"num_gaussians", trainer_->num_gaussians()}});
  const bool scored = !dataset_.test.empty();
  if (scored) {
    std::vector<Image> renders;
    last_test_ = trainer_->evaluate(dataset_.test, &renders);
    add_test_scores(history_.back(), *last_test_);
    fs::create_directories(options_.out / "test");
    for (std::size_t i = 0; i < renders.size(); ++i)
      write_png(renders[i], options_.out / "test" / (dataset_.test[i].name + ".png"));
  }
  const fs::path model_file = model_path();
  trainer_->write_model(model_file);
  std::error_code ignored;  // a watching viewer has moved on to the model by now
  fs::remove(snapshot_path(), ignored);
  const std::vector<fs::path> camera_files = write_view_cameras(*trainer_, dataset_, options_.out);
  const nlohmann::json m = metrics(stopped_by, train_seconds, fs::file_size(model_file));
  write_json(options_.out / "metrics.json", m);
  if (!options_.quiet && stopped_by == stop_reason_name(StopReason::kValidation))
    progress_.message(trainer_->finished_summary());
  if (!options_.quiet) {
    char line[256];
    std::snprintf(line, sizeof(line), "done: %d iterations in %s, %s", trainer_->iteration(),
                  format_duration(train_seconds).c_str(), trainer_->model_size().c_str());
    std::string done = line;
    if (scored) {
      std::snprintf(line, sizeof(line), ", test PSNR %.3f dB, SSIM %.4f (%d views)", last_test_->psnr,
                    last_test_->ssim, last_test_->views);
      done += line;
    } else {
      done += " (no test views: nothing scored)";
    }
    progress_.message(done);
    std::string cameras;
    for (const fs::path& file : camera_files) cameras += file.string() + ", ";
    progress_.message("outputs: " + model_file.string() + ", " + cameras + (options_.out / "metrics.json").string() +
                      (scored ? ", " + (options_.out / "test").string() + "/*.png" : std::string()));
  }
}

}  // namespace

int run_train_command(const TrainCommandOptions& options) {
  const auto thread_limit = limit_threads(options.threads);
  const Dataset dataset = load_dataset(options.data, options.dataset);
  if (dataset.train.empty()) throw InputError(options.data, "the dataset has no training views");
  if (!options.quiet && (options.group == nullptr || options.group->rank() == 0))
    std::printf("data: %s (%zu train, %zu test views, %s), scene extent %.3f\n",
                options.data.string().c_str(), dataset.train.size(), dataset.test.size(),
                dataset.points ? (std::to_string(dataset.points->size()) + " points").c_str()
                               : "no point cloud",
                dataset.scene_extent);
  if (!options.quiet && dataset.downscale != options.dataset.downscale &&
      (options.group == nullptr || options.group->rank() == 0))
    std::printf("images wider than %d pixels: training at 1/%d of their size (--downscale %d; give --downscale 1 "
                "to keep them)\n",
                options.dataset.max_width, dataset.downscale, dataset.downscale);
  TrainingRun run(options, dataset);
  return run.run();
}

}  // namespace splat::cli
