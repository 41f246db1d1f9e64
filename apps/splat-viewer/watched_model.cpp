#include "apps/splat-viewer/watched_model.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <thread>

#include "splat/core/error.hpp"

namespace splat::viewer {

namespace fs = std::filesystem;

namespace {

// What splat-train writes: the snapshot while it runs, the model when it is done.
constexpr const char* kModelNames[] = {"snapshot.ply", "snapshot.nerf", "snapshot.ngp",
                                       "model.ply",    "model.nerf",    "model.ngp"};

void check_folder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw InputError(dir, "no such folder (--watch takes splat-train's --out folder)");
  if (!fs::is_directory(dir, ec)) throw InputError(dir, "is not a folder (--watch takes splat-train's --out folder)");
}

std::string clock_time() {
  const std::time_t now = std::time(nullptr);
  char text[16];
  std::strftime(text, sizeof text, "%H:%M:%S", std::localtime(&now));
  return text;
}

}  // namespace

std::optional<fs::path> newest_model_in(const fs::path& dir) {
  std::optional<fs::path> newest;
  fs::file_time_type newest_time{};
  for (const char* name : kModelNames) {
    std::error_code ec;
    const fs::path file = dir / name;
    const fs::file_time_type time = fs::last_write_time(file, ec);
    if (ec) continue;
    if (!newest || time > newest_time) newest = file, newest_time = time;
  }
  return newest;
}

WatchedModel::WatchedModel(fs::path dir) : dir_(std::move(dir)) {
  check_folder(dir_);
  const std::optional<Seen> seen = newest();
  if (!seen) throw InputError(dir_, "holds no model yet (snapshot.ply, model.ply, or their .nerf or .ngp)");
  load(*seen);
  if (!model_) throw InputError(seen->file, status_);
}

std::optional<WatchedModel::Seen> WatchedModel::newest() const {
  const std::optional<fs::path> file = newest_model_in(dir_);
  if (!file) return std::nullopt;
  std::error_code ec;
  Seen seen{*file, fs::last_write_time(*file, ec), 0};
  if (!ec) seen.size = fs::file_size(*file, ec);
  if (ec) return std::nullopt;  // replaced between the two looks: the next refresh sees it
  return seen;
}

void WatchedModel::load(const Seen& seen) {
  shown_ = seen;  // a file that fails is not retried until it changes
  try {
    std::shared_ptr<PanelModel> loaded = load_panel_model(seen.file);
    {
      const std::lock_guard lock(mutex_);
      model_ = std::move(loaded);
    }
    ++version_;
    status_ = seen.file.filename().string() + " (" + clock_time() + ")";
  } catch (const std::exception& e) {
    status_ = e.what();
  }
}

bool WatchedModel::refresh() {
  const std::optional<Seen> seen = newest();
  if (!seen || seen == shown_) return false;
  const std::uint64_t before = version_;
  load(*seen);
  return version_ != before;
}

std::shared_ptr<PanelModel> WatchedModel::current() const {
  const std::lock_guard lock(mutex_);
  return model_;
}

void wait_for_first_model(const fs::path& dir, double timeout_seconds) {
  check_folder(dir);
  const auto start = std::chrono::steady_clock::now();
  bool said = false;
  while (!newest_model_in(dir)) {
    if (!said) std::printf("waiting for a model in %s (splat-train --snapshot-every S writes one)\n", dir.string().c_str());
    said = true;
    std::fflush(stdout);
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout_seconds)
      throw Error(dir.string() + ": no model appeared within " + std::to_string(int(timeout_seconds)) + " seconds");
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
}

}  // namespace splat::viewer
