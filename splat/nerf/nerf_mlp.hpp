#pragma once
// The NeRF network (Mildenhall et al. 2020, fig. 7), sizes as settings:
//
//   γ(x) ─► [ReLU, width] × depth ─┬─► linear width→1 ─► softplus | ReLU ─► σ ≥ 0
//          (layer skip_layer takes │
//           [h; γ(x)] as input)    └─► linear width→width (feature f, no activation)
//                                  [f; γ(d)] ─► ReLU, color_width ─► linear →3 ─► sigmoid ─► rgb
//
// γ(x) is positional_encoding.hpp's (raw input included, 3 + 6·position_frequencies inputs)
// or, with `encoding` "hash", Instant-NGP's multiresolution hash encoding (hash_encoding.hpp,
// levels·features inputs) of x's place in the network's input box; γ(d) is always the
// positional encoding of the unit view direction d (3 + 6·direction_frequencies inputs). A
// hash-encoded network with one narrow trunk layer is Instant-NGP's pair of tiny MLPs: the
// encoding carries the detail, the layers only decode it.
//
// Parameters live in one contiguous vector (Adam is one loop over it), layer after layer in
// the order of layers(): trunk 0 … depth−1, density, feature, colour, rgb; each layer is its
// weight W [out, in] column-major, then its bias b [out]. A concatenated input [A; B] is
// matched by W = [W_A | W_B] (columns of A first). Count (E_x, E_d the encoded sizes):
//   (E_x + 1)·width + (depth − 1)·(width + 1)·width + [skip] E_x·width      trunk
//   + (width + 1) + (width + 1)·width                                     density, feature
//   + (width + E_d + 1)·color_width + (color_width + 1)·3                 colour, rgb
// = 595,844 for the defaults. A hash-encoded network's tables follow the layers
// (HashGridLayout's order), initialised uniform in ±10⁻⁴ as the paper's.
//
// Initialisation (the reference TensorFlow NeRF's, Keras' Dense default): weights uniform in
// ±sqrt(6/(fan_in + fan_out)) (Glorot), biases zero; drawn from std::mt19937(seed) through
// splat::uniform01 in parameter order, so a seed gives the same network on every platform.
//
// Batches: forward and backward split the N samples into fixed-size chunks processed in
// parallel (oneTBB); inside a chunk each layer is one Eigen GEMM on column-major [features,
// chunk] activations (Eigen single-threaded: no OpenMP). Parameter gradients are summed into
// a fixed number of buffers, each taking a fixed share of the chunks in order, and the
// buffers are added in order, so the results are bit-identical for any thread count.
//
// Templated on the scalar so the gradient tests run the very same code in double;
// instantiated for float (NerfMlp, training) and double (tests).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <optional>

#include "splat/core/rays.hpp"
#include "splat/core/setting_value.hpp"
#include "splat/core/settings_table.hpp"
#include "splat/nerf/hash_encoding.hpp"
#include "splat/nerf/positional_encoding.hpp"

namespace splat {

// The largest network (docs/DESIGN.md §4.5): ~16M parameters (64 MB).
constexpr int kMaxNerfDepth = 16;
constexpr int kMaxNerfWidth = 1024;

enum class DensityActivation { kSoftplus, kRelu };
enum class PositionEncoding { kFrequency, kHash };

struct NerfMlpConfig {
  int position_frequencies = 10;  // L for γ(x)
  int direction_frequencies = 4;  // L for γ(d)
  int depth = 8;                  // trunk layers (ReLU, `width` outputs each)
  int width = 256;
  int skip_layer = 4;  // 0-based trunk layer whose input is [h; γ(x)]; −1 = none, else 1…depth−1
  int color_width = 128;
  DensityActivation density_activation = DensityActivation::kSoftplus;
  PositionEncoding encoding = PositionEncoding::kFrequency;
  HashEncodingSettings hash;  // used when encoding is kHash

  bool operator==(const NerfMlpConfig&) const = default;
};

// The network's settings as a .nerf or config file spells them (splat/core/settings_table.hpp).
template <class Table>
void describe_settings(Table& t, NerfMlpConfig& c) {
  const SettingRange frequencies{0, kMaxEncodingFrequencies};
  t.number("position_frequencies", c.position_frequencies, frequencies);
  t.number("direction_frequencies", c.direction_frequencies, frequencies);
  t.number("depth", c.depth, {1, kMaxNerfDepth});
  t.number("width", c.width, {1, kMaxNerfWidth});
  t.number("skip_layer", c.skip_layer, {-1, kMaxNerfDepth - 1});
  t.number("color_width", c.color_width, {1, kMaxNerfWidth});
  t.choice("density_activation", c.density_activation,
           {{"relu", DensityActivation::kRelu}, {"softplus", DensityActivation::kSoftplus}});
  t.choice("encoding", c.encoding, {{"frequency", PositionEncoding::kFrequency}, {"hash", PositionEncoding::kHash}});
  t.section("hash", c.hash);
}

// A positionally encoded network of these sizes, every other setting its default (the
// softplus density): the baseline's networks in a line each.
inline NerfMlpConfig frequency_mlp_config(int position_frequencies, int direction_frequencies, int depth, int width,
                                          int skip_layer, int color_width) {
  NerfMlpConfig c;
  c.position_frequencies = position_frequencies;
  c.direction_frequencies = direction_frequencies;
  c.depth = depth;
  c.width = width;
  c.skip_layer = skip_layer;
  c.color_width = color_width;
  return c;
}

// Reads a network's settings as a .nerf header or a config section spells them, every key
// needed except `encoding` and `hash`, which files written before the hash encoding lack
// (they read as the frequency encoding).
NerfMlpConfig read_nerf_mlp_config(const nlohmann::json& json, const SettingsReading& how);

// The size of γ(x), the trunk's input per sample.
int position_code_size(const NerfMlpConfig& config);

// Throws ArgumentError naming the first setting out of range ("path.key" under a `path`),
// or a skip layer that is neither −1 nor within the trunk.
void validate(const NerfMlpConfig& config, const std::string& path = "");

// One affine layer inside the parameter vector: W [out, in] column-major at `offset`,
// then b [out] at offset + out·in.
struct NerfLayerShape {
  std::size_t offset;
  int out;
  int in;
};

// What forward saves for backward, plus backward's scratch; buffers are sized on first use
// and grow only when a batch is larger than any before (no allocation per call otherwise).
// Activations are sample-major ([N, rows] = column-major [rows, N]); the stride between
// blocks is `capacity` samples.
template <typename Scalar>
struct BasicNerfMlpContext {
  std::size_t count = 0;     // N of the last forward
  std::size_t capacity = 0;  // samples the activation buffers hold
  NerfMlpConfig sized_for;   // the network these buffers were shaped for

  std::vector<Scalar> encoded_positions;      // [capacity, E_x] γ(x); its first 3 are x (frequency)
  std::vector<Scalar> unit_positions;         // [capacity, 3] x in the unit cube (hash)
  std::vector<Scalar> v_encoded_positions;    // [capacity, E_x] backward's ∂L/∂γ(x) (hash)
  std::vector<Scalar> encoded_directions;     // [capacity, E_d] γ(d)
  std::vector<Scalar> trunk;                  // depth × [capacity, width], after ReLU
  std::vector<Scalar> density_preactivation;  // [capacity] z, σ = act(z)
  std::vector<Scalar> feature;                // [capacity, width]
  std::vector<Scalar> color_hidden;           // [capacity, color_width], after ReLU
  std::vector<Scalar> rgb;                    // [capacity, 3], after the sigmoid

  std::vector<Scalar> partial_gradients;  // [slots, parameter_count]: one per chunk in flight
  std::vector<Scalar> backward_scratch;   // [slots, cotangents of one chunk]
};


template <typename Scalar>
class BasicNerfMlp {
 public:
  using Context = BasicNerfMlpContext<Scalar>;

  // The box a hash encoding spans (points outside are clamped to it); the frequency encoding
  // takes coordinates as they are.
  static AxisAlignedBox default_input_box() { return {glm::vec3(-1.5f), glm::vec3(1.5f)}; }

  // Validates the config (ArgumentError) and initialises the parameters from `seed`.
  explicit BasicNerfMlp(const NerfMlpConfig& config = {}, std::uint32_t seed = 0,
                        const AxisAlignedBox& input_box = default_input_box());

  const NerfMlpConfig& config() const { return config_; }
  std::size_t parameter_count() const { return parameters_.size(); }
  std::span<Scalar> parameters() { return parameters_; }
  std::span<const Scalar> parameters() const { return parameters_; }
  // trunk 0 … depth−1, then density, feature, colour, rgb (indices below).
  const std::vector<NerfLayerShape>& layers() const { return layers_; }
  int density_layer() const { return config_.depth; }
  int feature_layer() const { return config_.depth + 1; }
  int color_layer() const { return config_.depth + 2; }
  int rgb_layer() const { return config_.depth + 3; }
  // The layers' parameters come first; a hash encoding's tables follow them.
  std::size_t layer_parameter_count() const { return layer_parameter_count_; }
  const std::optional<HashGridLayout>& hash_layout() const { return hash_; }

  // positions, directions [N, 3] → sigma [N], rgb [N, 3]; fills `context` for backward.
  // Sizes must agree (ArgumentError).
  void forward(std::span<const Scalar> positions, std::span<const Scalar> directions,
               std::span<Scalar> sigma, std::span<Scalar> rgb, Context& context) const;
  // positions [N, 3] → sigma [N] only (σ does not depend on the direction): the trunk and the
  // density layer, the same arithmetic as forward's σ, without the colour branch (the
  // occupancy grid's queries). `context` is scratch; it does not prepare a backward.
  void forward_density(std::span<const Scalar> positions, std::span<Scalar> sigma, Context& context) const;

  // With the context of the last forward and cotangents v_sigma [N], v_rgb [N, 3]:
  // v_parameters [parameter_count()] += ∂L/∂θ, and, unless v_positions is empty (the
  // default: training needs no input gradient), v_positions [N, 3] += ∂L/∂x. The caller
  // zeroes both. The context is scratch here (its saved activations are only read). A hash
  // table's gradient is summed level by level, each level's samples in order, so it too is
  // the same for any thread count.
  void backward(Context& context, std::span<const Scalar> v_sigma, std::span<const Scalar> v_rgb,
                std::span<Scalar> v_parameters, std::span<Scalar> v_positions = {}) const;

 private:
  // Runs chunk(first, count) over [0, n) in fixed-size chunks, in parallel.
  template <typename ChunkFunction>
  void for_each_chunk(Context& context, std::size_t n, const ChunkFunction& chunk) const;
  // The trunk and σ of one chunk; then the colour branch on the trunk's last layer.
  void forward_density_chunk(Context& context, std::size_t first, std::size_t count, const Scalar* positions,
                             Scalar* sigma) const;
  void forward_color_chunk(Context& context, std::size_t first, std::size_t count, const Scalar* directions,
                           Scalar* rgb) const;
  void backward_chunk(Context& context, std::size_t slot, std::size_t first, std::size_t count,
                      const Scalar* v_sigma, const Scalar* v_rgb, Scalar* v_positions) const;
  void size_context(Context& context, std::size_t count) const;
  // γ(x) of one chunk into the context (and, for the hash encoding, x in the unit cube).
  void encode_positions_chunk(Context& context, std::size_t first, std::size_t count, const Scalar* positions) const;

  NerfMlpConfig config_;
  std::optional<HashGridLayout> hash_;
  glm::vec3 input_lo_{0.0f}, input_scale_{1.0f};  // unit = (x − lo)·scale (hash)
  std::size_t layer_parameter_count_ = 0;
  std::vector<NerfLayerShape> layers_;
  std::vector<Scalar> parameters_;  // [parameter_count()]
};

using NerfMlp = BasicNerfMlp<float>;
using NerfMlpContext = BasicNerfMlpContext<float>;

extern template class BasicNerfMlp<float>;
extern template class BasicNerfMlp<double>;

}  // namespace splat
