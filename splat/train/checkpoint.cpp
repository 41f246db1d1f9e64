// SplatTrainer checkpoints: a small binary container.
//   "SPLATCKP" | uint32 version | uint64 header bytes | header JSON | arrays
// Each array: uint64 element count, then that many little-endian float32. The arrays are the
// model's five parameter groups (kParameterGroups, in its order), then Adam's first and
// second moments (five each), then the density strategy's statistics
// (DensityStrategy::checkpoint_arrays: three for the official strategy, in the order every
// version-1 checkpoint has them), the per-view corrections' values and moments, and while the
// validation holdout is undecided and has a best model, that model's five groups, and while a
// parameter average is kept (the header's "parameter_average_from"), its offset's five groups.
#include <algorithm>
#include <cstdio>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

#include "splat/core/atomic_file.hpp"
#include "splat/core/file_bytes.hpp"
#include "splat/core/json_file.hpp"
#include "splat/core/setting_value.hpp"
#include "splat/train/splat_trainer.hpp"

namespace splat {

namespace {

constexpr char kMagic[8] = {'S', 'P', 'L', 'A', 'T', 'C', 'K', 'P'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint64_t kMaxHeaderBytes = 1 << 24;

void write_array(std::ostream& out, const std::vector<float>& a) {
  const std::uint64_t n = a.size();
  out.write(reinterpret_cast<const char*>(&n), sizeof(n));
  out.write(reinterpret_cast<const char*>(a.data()), std::streamsize(n * sizeof(float)));
}

void read_array(std::istream& in, std::vector<float>& a, std::uint64_t remaining_bytes,
                const std::filesystem::path& file) {
  std::uint64_t n = 0;
  if (!in.read(reinterpret_cast<char*>(&n), sizeof(n)))
    throw InputError(file, "checkpoint is truncated (array header)");
  if (n > remaining_bytes / sizeof(float))
    throw InputError(file, "checkpoint is truncated or corrupt (array larger than the file)");
  a.resize(n);
  if (!in.read(reinterpret_cast<char*>(a.data()), std::streamsize(n * sizeof(float))))
    throw InputError(file, "checkpoint is truncated (array data)");
}

}  // namespace

std::string SplatTrainer::train_images_fingerprint() const {
  if (train_images_fingerprint_.empty()) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(views_fingerprint(dataset_.train)));
    train_images_fingerprint_ = text;
  }
  return train_images_fingerprint_;
}

void SplatTrainer::save_checkpoint(const std::filesystem::path& file) const {
  nlohmann::json header;
  header["config"] = to_json(config_);
  header["iteration"] = iteration_;
  header["active_sh_degree"] = active_sh_degree_;
  header["sh_degree"] = model_.sh_degree;
  header["adam_step"] = adam_.step;
  header["view_stack"] = view_stack_;
  header["train_views"] = dataset_.train.size();
  header["downscale"] = dataset_.downscale;
  header["train_images"] = train_images_fingerprint();
  std::ostringstream rng_state;
  rng_state << rng_;
  header["rng"] = rng_state.str();
  header["strategy_state"] = strategy_->checkpoint_state();
  header["validation"] = holdout_.checkpoint_state();
  if (adam_.average_start) header["parameter_average_from"] = *adam_.average_start;
  // The training views' pose corrections and exposure maps, those that are on.
  const auto per_view = corrections_.states();
  for (const auto& state : per_view) header[state.steps_key] = state.adam->steps();
  const std::string text = header.dump();

  write_stream_atomically(file, [&](std::ostream& out) {
    out.write(kMagic, sizeof(kMagic));
    out.write(reinterpret_cast<const char*>(&kVersion), sizeof(kVersion));
    const std::uint64_t size = text.size();
    out.write(reinterpret_cast<const char*>(&size), sizeof(size));
    out.write(text.data(), std::streamsize(size));
    for (const GaussianModel* g : {&model_, &adam_.first_moment, &adam_.second_moment})
      for (const ParameterGroup& group : kParameterGroups) write_array(out, group.of(*g));
    for (const std::vector<float>* a : strategy_->checkpoint_arrays()) write_array(out, *a);
    for (const auto& state : per_view)  // the values and their Adam moments
      for (const std::vector<float>& a :
           {state.adam->parameters(), state.adam->first_moments(), state.adam->second_moments()})
        write_array(out, a);
    if (const GaussianModel* best = holdout_.checkpoint_model())
      for (const ParameterGroup& group : kParameterGroups) write_array(out, group.of(*best));
    if (adam_.averaging())
      for (const ParameterGroup& group : kParameterGroups) write_array(out, group.of(adam_.average_offset));
  });
}

void SplatTrainer::load_checkpoint(const std::filesystem::path& file, const GivenSettings& given) {
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(file, ec);
  if (ec) throw InputError(file, "cannot open the checkpoint: " + ec.message());
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, std::string("cannot open the checkpoint: ") + std::strerror(errno));
  char magic[8];
  std::uint32_t version = 0;
  std::uint64_t header_size = 0;
  if (!in.read(magic, sizeof(magic)) || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    throw InputError(file, "not a splat-train checkpoint (wrong magic)");
  if (!in.read(reinterpret_cast<char*>(&version), sizeof(version)) || version != kVersion)
    throw InputError(file, "checkpoint version " + std::to_string(version) + " is not " +
                               std::to_string(kVersion));
  if (!in.read(reinterpret_cast<char*>(&header_size), sizeof(header_size)) ||
      header_size > kMaxHeaderBytes || header_size > file_size)
    throw InputError(file, "checkpoint header is corrupt");
  std::string text(header_size, '\0');
  if (!in.read(text.data(), std::streamsize(header_size)))
    throw InputError(file, "checkpoint is truncated (header)");
  nlohmann::json header;
  std::optional<int> average_start;  // the parameter average's, if the run kept one
  try {
    header = nlohmann::json::parse(text);
    SplatTrainingConfig config = config_;
    from_json(resumed_settings(header.at("config"), to_json(config_), given), config);
    if (header.at("train_views").get<std::size_t>() != dataset_.train.size())
      throw InputError(file, "checkpoint was written for " +
                                 std::to_string(header.at("train_views").get<std::size_t>()) +
                                 " training views, this dataset has " +
                                 std::to_string(dataset_.train.size()));
    // Older checkpoints lack the fingerprint: for them only the count is compared.
    if (const auto images = header.find("train_images");
        images != header.end() && images->get<std::string>() != train_images_fingerprint())
      throw InputError(file, "checkpoint was written for other training images (the same number, other names or "
                             "pixels): resume it on the dataset it was trained on");
    if (const auto downscale = header.find("downscale");
        downscale != header.end() && downscale->get<int>() != dataset_.downscale)
      throw InputError(file, "checkpoint was trained on the images at 1/" + std::to_string(downscale->get<int>()) +
                                 " of their size, this run loads them at 1/" + std::to_string(dataset_.downscale) +
                                 ": give --downscale " + std::to_string(downscale->get<int>()) +
                                 " (or train afresh into another --out)");
    config_ = config;
    const SettingRange iterations{0, kMaxTrainingIterations}, sh_degrees{0, kMaxShDegree};
    iteration_ = read_setting<int>(header.at("iteration"), "iteration", iterations);
    active_sh_degree_ = read_setting<int>(header.at("active_sh_degree"), "active_sh_degree", sh_degrees);
    model_.sh_degree = adam_.first_moment.sh_degree = adam_.second_moment.sh_degree =
        read_setting<int>(header.at("sh_degree"), "sh_degree", sh_degrees);
    if (active_sh_degree_ > model_.sh_degree) throw ArgumentError("active_sh_degree is above sh_degree");
    adam_.step = read_setting<int>(header.at("adam_step"), "adam_step", iterations);
    view_stack_ = header.at("view_stack").get<std::vector<std::size_t>>();
    if (view_stack_.size() > dataset_.train.size()) throw ArgumentError("view_stack is longer than the views");
    std::istringstream rng_state(header.at("rng").get<std::string>());
    rng_state >> rng_;
    if (!rng_state) throw ArgumentError("rng is not a random generator's state");
    // The checkpoint's config also says which views the validation holdout takes.
    holdout_ = ValidationHoldout(dataset_, config_.validation);
    holdout_.checkpoint_state_loaded(header.value("validation", nlohmann::json()));
    if (const auto from = header.find("parameter_average_from"); from != header.end())
      average_start = read_setting<int>(*from, "parameter_average_from", iterations);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "checkpoint header is malformed: " + json_error_text(e));
  } catch (const ArgumentError& e) {
    throw InputError(file, e.what());
  }
  for (std::size_t v : view_stack_)
    if (v >= dataset_.train.size()) throw InputError(file, "checkpoint view order is corrupt");

  const std::uint64_t remaining = file_size - std::uint64_t(in.tellg());
  for (GaussianModel* g : {&model_, &adam_.first_moment, &adam_.second_moment})
    for (const ParameterGroup& group : kParameterGroups) read_array(in, group.of(*g), remaining, file);
  // The checkpoint's config named the strategy: its statistics follow the moments.
  strategy_ = make_density_strategy(config_, dataset_, 0);
  for (std::vector<float>* a : strategy_->checkpoint_arrays()) read_array(in, *a, remaining, file);
  // The checkpoint's config also says which per-view corrections there are.
  corrections_ = ViewCorrections(dataset_, config_, scene_extent_);
  const auto per_view = corrections_.states();
  std::vector<std::array<std::vector<float>, 3>> per_view_arrays(per_view.size());
  for (std::array<std::vector<float>, 3>& arrays : per_view_arrays)
    for (std::vector<float>& a : arrays) read_array(in, a, remaining, file);
  if (GaussianModel* best = holdout_.checkpoint_model())
    for (const ParameterGroup& group : kParameterGroups) read_array(in, group.of(*best), remaining, file);
  adam_.average_offset = GaussianModel{};  // as reset_like leaves it, unless the run kept an average
  adam_.average_start.reset();
  if (average_start) {
    adam_.start_average(model_, *average_start);
    for (const ParameterGroup& group : kParameterGroups)
      read_array(in, group.of(adam_.average_offset), remaining, file);
  }
  averaged_model_iteration_.reset();
  expect_end_of_file(in, file, "the checkpoint's last array");
  try {
    for (std::size_t k = 0; k < per_view.size(); ++k) {
      const std::array<std::vector<float>, 3>& a = per_view_arrays[k];
      per_view[k].adam->restore(a[0], a[1], a[2], header.at(per_view[k].steps_key).get<std::vector<long long>>());
    }
    model_.check_consistent();
    std::vector<GaussianModel*> rows = adam_.rows();
    for (const GaussianModel* g : rows) g->check_consistent();
    // A non-finite value would make the first step's model, and the last good one, non-finite.
    const auto finite = [](float v) { return std::isfinite(v); };
    rows.insert(rows.begin(), &model_);
    for (const GaussianModel* g : rows)
      for (const ParameterGroup& group : kParameterGroups)
        if (!std::all_of(group.of(*g).begin(), group.of(*g).end(), finite))
          throw ArgumentError(std::string(g == &model_ ? "a model" : "an Adam state") + " value is not finite");
    for (const GaussianModel* g : rows)
      if (g->size() != model_.size())
        throw ArgumentError("the Adam state (moments, parameter average) and the model disagree in length");
    strategy_->checkpoint_loaded(header.value("strategy_state", nlohmann::json::object()), model_.size());
    holdout_.checkpoint_model_loaded(model_.sh_degree);
  } catch (const ArgumentError& e) {
    throw InputError(file, std::string("checkpoint arrays are inconsistent: ") + e.what());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "checkpoint header is malformed: " + json_error_text(e));
  }
  last_good_model_ = model_;
}

}  // namespace splat
