#include "splat/train/batch_exchange.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "splat/core/error.hpp"

namespace splat {

namespace {

// A view's statistics travel as floats: its three loss figures (each double as two floats'
// bits, so they arrive exact), its image size, then [N] gradient norms, blending weights
// and radii (integers below 2²⁴, exact as floats).
constexpr std::size_t kViewHeaderFloats = 8;

std::size_t view_floats(std::size_t gaussians) { return kViewHeaderFloats + 3 * gaussians; }

void pack_double(double value, float* out) { std::memcpy(out, &value, sizeof(double)); }
double unpack_double(const float* in) {
  double value;
  std::memcpy(&value, in, sizeof(double));
  return value;
}

void pack_view(const ViewStatistics& view, std::size_t n, float* out) {
  pack_double(view.loss.loss, out);
  pack_double(view.loss.l1, out + 2);
  pack_double(view.loss.ssim, out + 4);
  out[6] = float(view.width);
  out[7] = float(view.height);
  out += kViewHeaderFloats;
  std::copy(view.viewspace_grad_norm.begin(), view.viewspace_grad_norm.end(), out);
  std::copy(view.blend_weight.begin(), view.blend_weight.end(), out + n);
  for (std::size_t i = 0; i < n; ++i) out[2 * n + i] = float(view.radii[i]);
}

void unpack_view(const float* in, std::size_t n, ViewStatistics& view) {
  view.loss = {unpack_double(in), unpack_double(in + 2), unpack_double(in + 4)};
  view.width = int(in[6]);
  view.height = int(in[7]);
  in += kViewHeaderFloats;
  view.viewspace_grad_norm.assign(in, in + n);
  view.blend_weight.assign(in + n, in + 2 * n);
  view.radii.resize(n);
  for (std::size_t i = 0; i < n; ++i) view.radii[i] = std::int32_t(in[2 * n + i]);
}

}  // namespace

GaussianModel& BatchExchange::exchange(ProcessGroup& group, const GaussianModel& block,
                                       std::span<ViewStatistics> views) {
  const std::size_t ranks = std::size_t(group.size()), rank = std::size_t(group.rank());
  if (views.size() % ranks != 0)
    throw ArgumentError("BatchExchange: " + std::to_string(views.size()) + " views over " + std::to_string(ranks) +
                        " ranks");
  const std::size_t per_rank = views.size() / ranks, n = block.size();
  const std::size_t values = block.value_count(), slice = (values + ranks - 1) / ranks;

  // 1. Slice q of every rank's block to rank q (the last slice padded with zeros), and this
  // rank's slice of the batch's sum, added up in place.
  slices_out_.resize(slice * ranks);
  block.write_values({slices_out_.data(), values});
  std::fill(slices_out_.begin() + std::ptrdiff_t(values), slices_out_.end(), 0.0f);
  slices_in_.resize(slice * ranks);
  group.all_to_all(slices_out_, slices_in_);
  slice_sum_.clear();
  for (std::size_t q = 0; q < ranks; ++q) {
    std::span<float> from_rank_q{slices_in_.data() + q * slice, slice};
    slice_sum_.take(from_rank_q);
  }
  const std::span<float> my_sum = slice_sum_.total();

  // 2. Every rank's summed slice, then every rank's views, to every rank.
  summed_slices_.resize(slice * ranks);
  group.all_gather(my_sum, summed_slices_);
  total_.sh_degree = block.sh_degree;
  total_.resize(n);
  total_.read_values({summed_slices_.data(), values});

  const std::size_t per_view = view_floats(n), views_message = per_rank * per_view;
  views_out_.resize(views_message);
  for (std::size_t v = 0; v < per_rank; ++v) pack_view(views[rank * per_rank + v], n, views_out_.data() + v * per_view);
  views_in_.resize(views_message * ranks);
  group.all_gather(views_out_, views_in_);
  for (std::size_t v = 0; v < views.size(); ++v) unpack_view(views_in_.data() + v * per_view, n, views[v]);

  report_.bytes_sent = sizeof(float) * (ranks - 1) * (2 * slice + views_message);
  report_.rows = n;
  drawn_.assign(n, 0);
  for (std::size_t v = 0; v < views.size(); ++v) {
    const std::uint8_t mark = v / per_rank == rank ? 3 : 2;  // this rank's views count for both
    for (std::size_t i = 0; i < n; ++i)
      if (views[v].radii[i] > 0) drawn_[i] |= mark;
  }
  const auto rows_with = [&](std::uint8_t bit) {
    return std::size_t(std::count_if(drawn_.begin(), drawn_.end(), [bit](std::uint8_t d) { return d & bit; }));
  };
  report_.block_visible_rows = rows_with(1);
  report_.batch_visible_rows = rows_with(2);
  return total_;
}

}  // namespace splat
