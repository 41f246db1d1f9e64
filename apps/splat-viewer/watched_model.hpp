#pragma once
// splat-viewer --watch DIR: the model a running splat-train writes into its output folder,
// followed as it improves. The trainer replaces DIR/snapshot.{ply,nerf} every few seconds
// (--snapshot-every) and writes DIR/model.{ply,nerf} at the end, each by an atomic rename, so
// a file seen here is always whole; the newest of them is shown. The render worker and the
// window may ask for the model at any moment while the window thread swaps in a new one, so
// each call takes its own reference to the model of the moment.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "apps/splat-viewer/panel_model.hpp"

namespace splat::viewer {

// The files a training output folder may hold a model in, newest first by modification time;
// empty when it has none yet.
std::optional<std::filesystem::path> newest_model_in(const std::filesystem::path& dir);

class WatchedModel final : public PanelModel {
 public:
  // Loads the newest model in `dir`. InputError naming the folder when it is not one or holds
  // no model yet (wait_for_first_model waits for one).
  explicit WatchedModel(std::filesystem::path dir);

  // Looks at the folder again and loads a model newer than the one shown (another file, or
  // the same file replaced). Returns true when the model changed. A file that fails to load
  // keeps the model shown and says why in status().
  bool refresh();
  // Counts the models loaded: a frame rendered under another version is out of date.
  std::uint64_t version() const { return version_; }
  // "snapshot.ply (12:04:31)" or the last load's error.
  const std::string& status() const { return status_; }

  std::string description() const override { return current()->description(); }
  std::size_t gaussian_count() const override { return current()->gaussian_count(); }
  int max_sh_degree() const override { return current()->max_sh_degree(); }
  bool progressive() const override { return current()->progressive(); }
  std::vector<float> framing_points() const override { return current()->framing_points(); }
  bool render(const Camera& camera, const ViewSettings& settings, const std::atomic<bool>& cancel,
              PanelFrame& frame) override {
    return current()->render(camera, settings, cancel, frame);
  }

 private:
  struct Seen {
    std::filesystem::path file;
    std::filesystem::file_time_type time;
    std::uintmax_t size = 0;
    bool operator==(const Seen&) const = default;
  };
  std::shared_ptr<PanelModel> current() const;
  std::optional<Seen> newest() const;
  void load(const Seen& seen);

  std::filesystem::path dir_;
  mutable std::mutex mutex_;  // guards model_ (the pointer, not the model it points to)
  std::shared_ptr<PanelModel> model_;
  std::optional<Seen> shown_;
  std::uint64_t version_ = 0;
  std::string status_;
};

// Waits until `dir` holds a model, printing once what it waits for; InputError when `dir` is
// not a folder, Error after `timeout_seconds`.
void wait_for_first_model(const std::filesystem::path& dir, double timeout_seconds);

}  // namespace splat::viewer
