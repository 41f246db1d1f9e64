// forward_single: the network written as the paper draws it, one sample,
// plain loops over the same parameter vector. Slow and allocating on purpose; it shares no
// code with the batched forward besides the encoding, so it is the tests' oracle for the
// GEMM layout (column-major W, split concatenations, chunking).
#include <vector>

#include "tests/nerf/nerf_mlp_reference.hpp"

#include "splat/nerf/dense_layer.hpp"
#include "splat/nerf/positional_encoding.hpp"

namespace splat::test {
namespace {

// y = W·x + b for one sample, with W [out, in] column-major at layer.offset.
template <typename Scalar>
std::vector<Scalar> affine(const std::vector<Scalar>& params, const NerfLayerShape& layer,
                           const std::vector<Scalar>& x) {
  const Scalar* w = params.data() + layer.offset;
  const Scalar* b = w + std::size_t(layer.out) * layer.in;
  std::vector<Scalar> y(layer.out);
  for (int r = 0; r < layer.out; ++r) {
    Scalar sum = b[r];
    for (int c = 0; c < layer.in; ++c) sum += w[r + std::size_t(c) * layer.out] * x[c];
    y[r] = sum;
  }
  return y;
}

template <typename Scalar>
std::vector<Scalar> relu(std::vector<Scalar> v) {
  for (Scalar& x : v) x = nerf_detail::relu(x);
  return v;
}

template <typename Scalar>
std::vector<Scalar> concat(std::vector<Scalar> a, const std::vector<Scalar>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

template <typename Scalar>
NerfMlpSample<Scalar> forward_single(const BasicNerfMlp<Scalar>& mlp, const Scalar* position,
                                     const Scalar* direction) {
  const NerfMlpConfig& config = mlp.config();
  const std::vector<NerfLayerShape>& layers = mlp.layers();
  std::vector<Scalar> gx(encoded_size(config.position_frequencies));
  std::vector<Scalar> gd(encoded_size(config.direction_frequencies));
  encode(position, config.position_frequencies, gx.data());
  encode(direction, config.direction_frequencies, gd.data());
  const std::vector<Scalar> params(mlp.parameters().begin(), mlp.parameters().end());

  std::vector<Scalar> h = gx;
  for (int i = 0; i < config.depth; ++i)
    h = relu(affine(params, layers[i], i == config.skip_layer ? concat(h, gx) : h));

  const Scalar z = affine(params, layers[mlp.density_layer()], h)[0];
  NerfMlpSample<Scalar> out;
  out.sigma = config.density_activation == DensityActivation::kSoftplus
                  ? nerf_detail::softplus(z)
                  : nerf_detail::relu(z);
  const std::vector<Scalar> f = affine(params, layers[mlp.feature_layer()], h);
  const std::vector<Scalar> hidden = relu(affine(params, layers[mlp.color_layer()], concat(f, gd)));
  const std::vector<Scalar> o = affine(params, layers[mlp.rgb_layer()], hidden);
  for (int k = 0; k < 3; ++k) out.rgb[k] = sigmoid(o[k]);
  return out;
}

template NerfMlpSample<float> forward_single(const BasicNerfMlp<float>&, const float*, const float*);
template NerfMlpSample<double> forward_single(const BasicNerfMlp<double>&, const double*, const double*);

}  // namespace splat::test
