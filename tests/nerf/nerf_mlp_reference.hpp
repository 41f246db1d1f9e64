#pragma once
// The tests' oracle for the batched NeRF MLP: one sample through plain loops, no Eigen, no
// chunks.
#include <array>

#include "splat/nerf/nerf_mlp.hpp"

namespace splat::test {

// One sample's outputs.
template <typename Scalar>
struct NerfMlpSample {
  Scalar sigma;
  std::array<Scalar, 3> rgb;
};

// `mlp` at one sample (position [3], direction [3]).
template <typename Scalar>
NerfMlpSample<Scalar> forward_single(const BasicNerfMlp<Scalar>& mlp, const Scalar* position,
                                     const Scalar* direction);

}  // namespace splat::test
