#pragma once
// A built-in procedural model, so a new user can render something before having data:
// a sphere covered by flat Gaussians in a coloured latitude/longitude pattern, circled by
// a ring. Deterministic for a given seed.
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

GaussianModel make_demo_model(int gaussian_count = 20000, unsigned seed = 1);

}  // namespace splat
