#include "splat/nerf/nerf_mlp.hpp"

// First: it must precede oneTBB's headers (see eigen_core.hpp).
#include "splat/nerf/eigen_core.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"
#include "splat/core/settings_table.hpp"
#include "splat/nerf/dense_layer.hpp"
#include "splat/nerf/positional_encoding.hpp"

namespace splat {
namespace {

using nerf_detail::Activation;
using nerf_detail::ConstMatrixRef;
using nerf_detail::MatrixRef;

// Samples per task. Fixed, so chunk boundaries (hence every GEMM's shape and rounding) do
// not depend on the thread count; 256 columns of 256 floats is 256 KB per activation
// block, so a layer's input and output stay in a core's L2.
constexpr std::size_t kSamplesPerChunk = 256;
// Parameter-gradient buffers of a backward pass, each summing a fixed share of the chunks
// (parameter_count floats each: 2.4 MB for the defaults). A fixed number, not one per
// thread, so the order of the additions is the same for any thread count.
constexpr std::size_t kGradientSlots = 8;
// Parameters per task when the partial gradients are added together.
constexpr std::size_t kParametersPerReduceTask = 16384;

template <typename Scalar>
using Map = Eigen::Map<nerf_detail::Matrix<Scalar>>;
template <typename Scalar>
using ConstMap = Eigen::Map<const nerf_detail::Matrix<Scalar>>;
template <typename Scalar>
using VectorMap = Eigen::Map<nerf_detail::Vector<Scalar>>;
template <typename Scalar>
using ConstVectorMap = Eigen::Map<const nerf_detail::Vector<Scalar>>;

// W and b of `layer` inside a parameter-shaped buffer (the parameters or a gradient).
template <typename Scalar>
ConstMap<Scalar> weight(const Scalar* base, const NerfLayerShape& layer) {
  return ConstMap<Scalar>(base + layer.offset, layer.out, layer.in);
}
template <typename Scalar>
ConstVectorMap<Scalar> bias(const Scalar* base, const NerfLayerShape& layer) {
  return ConstVectorMap<Scalar>(base + layer.offset + std::size_t(layer.out) * layer.in,
                                layer.out);
}
template <typename Scalar>
Map<Scalar> weight(Scalar* base, const NerfLayerShape& layer) {
  return Map<Scalar>(base + layer.offset, layer.out, layer.in);
}
template <typename Scalar>
VectorMap<Scalar> bias(Scalar* base, const NerfLayerShape& layer) {
  return VectorMap<Scalar>(base + layer.offset + std::size_t(layer.out) * layer.in, layer.out);
}

// Columns [first, first + count) of a [rows, capacity] block starting at `block`.
template <typename Scalar>
Map<Scalar> columns(Scalar* block, int rows, std::size_t first, std::size_t count) {
  return Map<Scalar>(block + std::size_t(rows) * first, rows, Eigen::Index(count));
}
template <typename Scalar>
ConstMap<Scalar> columns(const Scalar* block, int rows, std::size_t first, std::size_t count) {
  return ConstMap<Scalar>(block + std::size_t(rows) * first, rows, Eigen::Index(count));
}

// Columns [first, first + n) of trunk layer `layer`'s activations in `ctx`.
template <typename Scalar>
Map<Scalar> trunk_columns(BasicNerfMlpContext<Scalar>& ctx, const NerfMlpConfig& config, int layer, std::size_t first,
                          std::size_t n) {
  return columns(ctx.trunk.data() + std::size_t(layer) * std::size_t(config.width) * ctx.capacity, config.width,
                 first, n);
}

// Rows of one chunk's cotangent scratch (backward_chunk lays them out): two ping-pong
// [width] blocks for the trunk, the colour hidden layer, rgb, density, and γ(x).
std::size_t cotangent_rows(const NerfMlpConfig& c) {
  return std::size_t(2 * c.width + c.color_width + 3 + 1 + position_code_size(c));
}

std::size_t chunk_count(std::size_t samples) {
  return (samples + kSamplesPerChunk - 1) / kSamplesPerChunk;
}

void require(bool ok, const std::string& message) {
  if (!ok) throw ArgumentError("NeRF MLP: " + message);
}

}  // namespace

int position_code_size(const NerfMlpConfig& c) {
  return c.encoding == PositionEncoding::kHash ? c.hash.levels * c.hash.features
                                               : encoded_size(c.position_frequencies);
}

NerfMlpConfig read_nerf_mlp_config(const nlohmann::json& json, const SettingsReading& how) {
  SettingsReading reading = how;
  reading.optional.insert(reading.optional.end(), {"encoding", "hash"});
  return settings_from_json<NerfMlpConfig>(json, reading);
}

void validate(const NerfMlpConfig& c, const std::string& path) {
  check_setting_ranges(c, path);
  validate(c.hash, (path.empty() ? "" : path + ".") + "hash");
  // Layer 0 already takes γ(x) alone; a skip there would only duplicate its input.
  if (!(c.skip_layer == -1 || (c.skip_layer >= 1 && c.skip_layer < c.depth)))
    throw ArgumentError("\"" + (path.empty() ? "" : path + ".") + "skip_layer\" must be -1 or from 1 to depth - 1 (got " +
                        std::to_string(c.skip_layer) + ")");
}

template <typename Scalar>
BasicNerfMlp<Scalar>::BasicNerfMlp(const NerfMlpConfig& config, std::uint32_t seed, const AxisAlignedBox& input_box)
    : config_(config) {
  validate(config_);
  if (config_.encoding == PositionEncoding::kHash) {
    hash_.emplace(config_.hash);
    const glm::vec3 size = input_box.hi - input_box.lo;
    require(size.x > 0 && size.y > 0 && size.z > 0, "the hash encoding's input box is empty");
    input_lo_ = input_box.lo;
    input_scale_ = 1.0f / size;
  }
  const int ex = position_code_size(config_);
  const int ed = encoded_size(config_.direction_frequencies);
  const int w = config_.width;
  std::size_t offset = 0;
  const auto add = [&](int out, int in) {
    layers_.push_back({offset, out, in});
    offset += std::size_t(out) * std::size_t(in + 1);
  };
  for (int i = 0; i < config_.depth; ++i)
    add(w, i == 0 ? ex : (i == config_.skip_layer ? w + ex : w));
  add(1, w);                                   // density
  add(w, w);                                   // feature
  add(config_.color_width, w + ed);            // colour hidden, on [f; γ(d)]
  add(3, config_.color_width);                 // rgb
  layer_parameter_count_ = offset;
  parameters_.assign(offset + (hash_ ? hash_->parameter_count() : 0), Scalar(0));

  std::mt19937 rng(seed);
  for (const NerfLayerShape& layer : layers_) {
    const double bound = std::sqrt(6.0 / double(layer.in + layer.out));
    Scalar* w_begin = parameters_.data() + layer.offset;
    for (std::size_t k = 0; k < std::size_t(layer.out) * layer.in; ++k)
      w_begin[k] = Scalar(bound * (2.0 * double(uniform01(rng)) - 1.0));
  }
  // Small, so the untrained encoding adds almost nothing and each entry grows only as far as
  // its gradients take it (the paper's ±10⁻⁴).
  for (std::size_t k = layer_parameter_count_; k < parameters_.size(); ++k)
    parameters_[k] = Scalar(1e-4 * (2.0 * double(uniform01(rng)) - 1.0));
}

template <typename Scalar>
void BasicNerfMlp<Scalar>::size_context(Context& ctx, std::size_t count) const {
  if (!(ctx.sized_for == config_) || ctx.encoded_positions.empty()) {
    ctx = Context{};
    ctx.sized_for = config_;
  }
  if (count <= ctx.capacity) return;
  const std::size_t ex = position_code_size(config_);
  const std::size_t ed = encoded_size(config_.direction_frequencies);
  const std::size_t w = config_.width;
  ctx.capacity = count;
  ctx.encoded_positions.resize(ex * count);
  if (hash_) {
    ctx.unit_positions.resize(3 * count);
    ctx.v_encoded_positions.resize(ex * count);
  }
  ctx.encoded_directions.resize(ed * count);
  ctx.trunk.resize(std::size_t(config_.depth) * w * count);
  ctx.density_preactivation.resize(count);
  ctx.feature.resize(w * count);
  ctx.color_hidden.resize(std::size_t(config_.color_width) * count);
  ctx.rgb.resize(3 * count);
}

template <typename Scalar>
void BasicNerfMlp<Scalar>::forward(std::span<const Scalar> positions,
                                   std::span<const Scalar> directions, std::span<Scalar> sigma,
                                   std::span<Scalar> rgb, Context& context) const {
  const std::size_t n = positions.size() / 3;
  require(positions.size() == 3 * n, "positions must hold 3 floats per sample");
  require(directions.size() == 3 * n, "directions must match positions ([N, 3])");
  require(sigma.size() == n, "sigma must hold N values");
  require(rgb.size() == 3 * n, "rgb must hold 3 N values");
  for_each_chunk(context, n, [&](std::size_t first, std::size_t count) {
    forward_density_chunk(context, first, count, positions.data(), sigma.data());
    forward_color_chunk(context, first, count, directions.data(), rgb.data());
  });
}

template <typename Scalar>
void BasicNerfMlp<Scalar>::forward_density(std::span<const Scalar> positions, std::span<Scalar> sigma,
                                           Context& context) const {
  const std::size_t n = positions.size() / 3;
  require(positions.size() == 3 * n, "positions must hold 3 floats per sample");
  require(sigma.size() == n, "sigma must hold N values");
  for_each_chunk(context, n, [&](std::size_t first, std::size_t count) {
    forward_density_chunk(context, first, count, positions.data(), sigma.data());
  });
}

template <typename Scalar>
template <typename ChunkFunction>
void BasicNerfMlp<Scalar>::for_each_chunk(Context& context, std::size_t n, const ChunkFunction& chunk) const {
  size_context(context, n);
  context.count = n;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, chunk_count(n), 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t c = range.begin(); c != range.end(); ++c) {
          const std::size_t first = c * kSamplesPerChunk;
          chunk(first, std::min(kSamplesPerChunk, n - first));
        }
      },
      tbb::simple_partitioner());
}

template <typename Scalar>
void BasicNerfMlp<Scalar>::forward_density_chunk(Context& ctx, std::size_t first, std::size_t n,
                                                 const Scalar* positions, Scalar* sigma) const {
  const Scalar* params = parameters_.data();
  const auto trunk = [&](int i) { return trunk_columns(ctx, config_, i, first, n); };
  encode_positions_chunk(ctx, first, n, positions);
  Map<Scalar> gx = columns(ctx.encoded_positions.data(), position_code_size(config_), first, n);  // [E_x, n]

  for (int i = 0; i < config_.depth; ++i) {
    const NerfLayerShape& layer = layers_[i];
    if (i == 0)
      nerf_detail::dense_forward<Scalar>(weight(params, layer), bias(params, layer), gx,
                                         Activation::kRelu, trunk(0));
    else if (i == config_.skip_layer)
      nerf_detail::dense2_forward<Scalar>(weight(params, layer), bias(params, layer),
                                          trunk(i - 1), gx, Activation::kRelu, trunk(i));
    else
      nerf_detail::dense_forward<Scalar>(weight(params, layer), bias(params, layer),
                                         trunk(i - 1), Activation::kRelu, trunk(i));
  }
  const Map<Scalar> last = trunk(config_.depth - 1);  // [width, n]

  const NerfLayerShape& density = layers_[density_layer()];
  Map<Scalar> z = columns(ctx.density_preactivation.data(), 1, first, n);  // [1, n]
  nerf_detail::dense_forward<Scalar>(weight(params, density), bias(params, density), last,
                                     Activation::kNone, z);
  const bool softplus = config_.density_activation == DensityActivation::kSoftplus;
  for (std::size_t j = 0; j < n; ++j)
    sigma[first + j] = softplus ? nerf_detail::softplus(z(0, j)) : nerf_detail::relu(z(0, j));
}

template <typename Scalar>
void BasicNerfMlp<Scalar>::encode_positions_chunk(Context& ctx, std::size_t first, std::size_t n,
                                                  const Scalar* positions) const {
  Scalar* code = ctx.encoded_positions.data() + std::size_t(position_code_size(config_)) * first;
  if (!hash_) {
    encode_batch(positions + 3 * first, n, config_.position_frequencies, code);
    return;
  }
  Scalar* unit = ctx.unit_positions.data() + 3 * first;
  for (std::size_t j = 0; j < n; ++j)
    for (int a = 0; a < 3; ++a)
      unit[3 * j + a] = (positions[3 * (first + j) + a] - Scalar(input_lo_[a])) * Scalar(input_scale_[a]);
  hash_encode(*hash_, parameters_.data() + layer_parameter_count_, unit, n, code);
}

template <typename Scalar>
void BasicNerfMlp<Scalar>::forward_color_chunk(Context& ctx, std::size_t first, std::size_t n,
                                               const Scalar* directions, Scalar* rgb) const {
  const int w = config_.width;
  const Scalar* params = parameters_.data();
  const Map<Scalar> last = trunk_columns(ctx, config_, config_.depth - 1, first, n);
  Map<Scalar> gd = columns(ctx.encoded_directions.data(), encoded_size(config_.direction_frequencies), first, n);
  encode_batch(directions + 3 * first, n, config_.direction_frequencies, gd.data());  // [E_d, n]

  const NerfLayerShape& feature = layers_[feature_layer()];
  Map<Scalar> f = columns(ctx.feature.data(), w, first, n);  // [width, n]
  nerf_detail::dense_forward<Scalar>(weight(params, feature), bias(params, feature), last,
                                     Activation::kNone, f);

  const NerfLayerShape& color = layers_[color_layer()];
  Map<Scalar> hidden = columns(ctx.color_hidden.data(), config_.color_width, first, n);
  nerf_detail::dense2_forward<Scalar>(weight(params, color), bias(params, color), f, gd,
                                      Activation::kRelu, hidden);

  const NerfLayerShape& out = layers_[rgb_layer()];
  Map<Scalar> c = columns(ctx.rgb.data(), 3, first, n);  // [3, n]
  nerf_detail::dense_forward<Scalar>(weight(params, out), bias(params, out), hidden,
                                     Activation::kNone, c);
  Scalar* rgb_out = rgb + 3 * first;
  for (std::size_t k = 0; k < 3 * n; ++k) {
    c.data()[k] = sigmoid(c.data()[k]);
    rgb_out[k] = c.data()[k];
  }
}

template <typename Scalar>
void BasicNerfMlp<Scalar>::backward(Context& ctx, std::span<const Scalar> v_sigma,
                                    std::span<const Scalar> v_rgb,
                                    std::span<Scalar> v_parameters,
                                    std::span<Scalar> v_positions) const {
  const std::size_t n = ctx.count;
  require(ctx.sized_for == config_ && ctx.capacity >= n,
          "backward needs the context of this network's forward");
  require(v_sigma.size() == n, "v_sigma must hold N values (N of the last forward)");
  require(v_rgb.size() == 3 * n, "v_rgb must hold 3 N values");
  require(v_parameters.size() == parameter_count(), "v_parameters must hold parameter_count()");
  require(v_positions.empty() || v_positions.size() == 3 * n,
          "v_positions must be empty or hold 3 N values");

  const std::size_t p = layer_parameter_count_;
  if (ctx.partial_gradients.size() < kGradientSlots * p) {
    ctx.partial_gradients.resize(kGradientSlots * p);
    ctx.backward_scratch.resize(kGradientSlots * kSamplesPerChunk * cotangent_rows(config_));
  }
  Scalar* v_x = v_positions.empty() ? nullptr : v_positions.data();

  // Slot s takes chunks s, s + S, s + 2S, … in that order, summing their gradients into its
  // own buffer; the slots are then added in slot order. The assignment and both orders are
  // fixed, so the sums are the same for any thread count; each buffer is zeroed once per call,
  // not once per chunk.
  const std::size_t chunks = chunk_count(n), slots = std::min(chunks, kGradientSlots);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, slots, 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t s = range.begin(); s != range.end(); ++s) {
          std::fill_n(ctx.partial_gradients.data() + s * p, p, Scalar(0));
          for (std::size_t c = s; c < chunks; c += slots) {
            const std::size_t first = c * kSamplesPerChunk;
            backward_chunk(ctx, s, first, std::min(kSamplesPerChunk, n - first), v_sigma.data(), v_rgb.data(), v_x);
          }
        }
      },
      tbb::simple_partitioner());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, p, kParametersPerReduceTask),
      [&](const tbb::blocked_range<std::size_t>& range) {
        Scalar* __restrict out = v_parameters.data();
        for (std::size_t s = 0; s < slots; ++s) {
          const Scalar* __restrict partial = ctx.partial_gradients.data() + s * p;
          for (std::size_t k = range.begin(); k != range.end(); ++k) out[k] += partial[k];
        }
      },
      tbb::simple_partitioner());
  if (!hash_) return;
  // The tables: one task per level, each adding its samples' cotangents in sample order.
  tbb::parallel_for(
      tbb::blocked_range<int>(0, int(hash_->levels().size()), 1),
      [&](const tbb::blocked_range<int>& range) {
        for (int level = range.begin(); level != range.end(); ++level)
          hash_encode_vjp_table(*hash_, level, ctx.unit_positions.data(), n, ctx.v_encoded_positions.data(),
                                v_parameters.data() + layer_parameter_count_);
      },
      tbb::simple_partitioner());
}

// The chain rule backwards through forward_density_chunk and forward_color_chunk, one layer's
// VJP at a time (dense_layer.hpp holds each VJP and its derivation). Parameter gradients go
// to this slot's own buffer.
template <typename Scalar>
void BasicNerfMlp<Scalar>::backward_chunk(Context& ctx, std::size_t slot, std::size_t first,
                                          std::size_t n, const Scalar* v_sigma,
                                          const Scalar* v_rgb, Scalar* v_positions) const {
  const int ex = position_code_size(config_);
  const int ed = encoded_size(config_.direction_frequencies);
  const int w = config_.width;
  const int cw = config_.color_width;
  const std::size_t p = layer_parameter_count_;
  const Scalar* params = parameters_.data();
  Scalar* grad = ctx.partial_gradients.data() + slot * p;  // accumulates this slot's chunks
  const Context& saved = ctx;  // forward's activations: read only
  const auto trunk = [&](int i) {
    return columns(saved.trunk.data() + std::size_t(i) * w * saved.capacity, w, first, n);
  };

  // This slot's cotangent scratch, in cotangent_rows' order.
  Scalar* scratch = ctx.backward_scratch.data() + slot * kSamplesPerChunk * cotangent_rows(config_);
  const auto take = [&](int rows) {
    Map<Scalar> m(scratch, rows, Eigen::Index(n));
    scratch += std::size_t(rows) * kSamplesPerChunk;
    return m;
  };
  MatrixRef<Scalar> v_a = take(w), v_b = take(w), v_hidden = take(cw), v_c = take(3),
                    v_z = take(1), v_gx_scratch = take(ex);
  // The hash encoding's cotangent outlives the chunk: the tables' VJP runs after all chunks.
  Map<Scalar> v_gx_saved = hash_ ? columns(ctx.v_encoded_positions.data(), ex, first, n) : Map<Scalar>(nullptr, 0, 0);
  MatrixRef<Scalar> v_gx = hash_ ? MatrixRef<Scalar>(v_gx_saved) : v_gx_scratch;

  const ConstMap<Scalar> gx = columns(saved.encoded_positions.data(), ex, first, n);
  const ConstMap<Scalar> gd = columns(saved.encoded_directions.data(), ed, first, n);
  const ConstMap<Scalar> last = trunk(config_.depth - 1);
  const ConstMap<Scalar> f = columns(saved.feature.data(), w, first, n);
  const ConstMap<Scalar> hidden = columns(saved.color_hidden.data(), cw, first, n);
  const ConstMap<Scalar> c = columns(saved.rgb.data(), 3, first, n);

  // rgb = sigmoid(o):  v_o = v_rgb · rgb · (1 − rgb).
  for (std::size_t k = 0; k < 3 * n; ++k)
    v_c.data()[k] = nerf_detail::sigmoid_vjp_from_output(c.data()[k], v_rgb[3 * first + k]);
  const NerfLayerShape& out = layers_[rgb_layer()];
  v_hidden.setZero();
  nerf_detail::dense_vjp<Scalar>(weight(params, out), hidden, v_c, weight(grad, out),
                                 bias(grad, out), &v_hidden);
  nerf_detail::relu_vjp_inplace<Scalar>(hidden, v_hidden);

  // Colour layer on [f; γ(d)]: only f's cotangent is wanted (directions are not trained).
  const NerfLayerShape& color = layers_[color_layer()];
  v_a.setZero();
  nerf_detail::dense2_vjp<Scalar>(weight(params, color), f, gd, v_hidden, weight(grad, color),
                                  bias(grad, color), &v_a, nullptr);

  // f = W_f·h + b_f (no activation): v_h = W_fᵀ·v_f, into v_b.
  const NerfLayerShape& feature = layers_[feature_layer()];
  v_b.setZero();
  nerf_detail::dense_vjp<Scalar>(weight(params, feature), last, v_a, weight(grad, feature),
                                 bias(grad, feature), &v_b);

  // σ = act(z): v_z = v_σ · act'(z); then the density layer adds w_σᵀ·v_z to v_h.
  const bool softplus = config_.density_activation == DensityActivation::kSoftplus;
  const Scalar* z = saved.density_preactivation.data() + first;
  for (std::size_t j = 0; j < n; ++j)
    v_z(0, Eigen::Index(j)) = softplus ? nerf_detail::softplus_vjp(z[j], v_sigma[first + j])
                                       : nerf_detail::relu_vjp(z[j], v_sigma[first + j]);
  const NerfLayerShape& density = layers_[density_layer()];
  nerf_detail::dense_vjp<Scalar>(weight(params, density), last, v_z, weight(grad, density),
                                 bias(grad, density), &v_b);

  // Trunk, top down; `v_h` holds the cotangent of layer i's output.
  MatrixRef<Scalar>* v_h = &v_b;
  MatrixRef<Scalar>* v_below = &v_a;
  MatrixRef<Scalar>* v_code = v_positions || hash_ ? &v_gx : nullptr;
  if (v_code) v_gx.setZero();
  for (int i = config_.depth - 1; i >= 0; --i) {
    const NerfLayerShape& layer = layers_[i];
    nerf_detail::relu_vjp_inplace<Scalar>(trunk(i), *v_h);
    if (i == 0) {
      nerf_detail::dense_vjp<Scalar>(weight(params, layer), gx, *v_h, weight(grad, layer),
                                     bias(grad, layer), v_code);
      break;
    }
    v_below->setZero();
    if (i == config_.skip_layer)
      nerf_detail::dense2_vjp<Scalar>(weight(params, layer), trunk(i - 1), gx, *v_h,
                                      weight(grad, layer), bias(grad, layer), v_below, v_code);
    else
      nerf_detail::dense_vjp<Scalar>(weight(params, layer), trunk(i - 1), *v_h,
                                     weight(grad, layer), bias(grad, layer), v_below);
    std::swap(v_h, v_below);
  }

  if (hash_) {
    if (!v_positions) return;
    // ∂u/∂x = scale per axis.
    const Scalar* unit = saved.unit_positions.data() + 3 * first;
    Scalar* v_x = v_positions + 3 * first;
    std::vector<Scalar> v_unit(3 * n, Scalar(0));
    hash_encode_vjp_positions(*hash_, params + layer_parameter_count_, unit, n, v_gx.data(), v_unit.data());
    for (std::size_t j = 0; j < n; ++j)
      for (int a = 0; a < 3; ++a) v_x[3 * j + a] += v_unit[3 * j + a] * Scalar(input_scale_[a]);
    return;
  }
  // γ(x)'s first three rows are x itself, so the encoding's VJP needs no other input.
  if (v_code)
    for (std::size_t j = 0; j < n; ++j)
      encode_vjp(gx.data() + std::size_t(ex) * j, config_.position_frequencies,
                 v_gx.data() + std::size_t(ex) * j, v_positions + 3 * (first + j));
}

template class BasicNerfMlp<float>;
template class BasicNerfMlp<double>;

}  // namespace splat
