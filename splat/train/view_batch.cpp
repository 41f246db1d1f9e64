#include "splat/train/view_batch.hpp"

namespace splat {

void add_into(std::span<float> a, std::span<const float> b) {
  if (a.size() != b.size())
    throw ArgumentError("add_into: " + std::to_string(a.size()) + " values and " + std::to_string(b.size()));
  for (std::size_t i = 0; i < a.size(); ++i) a[i] += b[i];
}

}  // namespace splat
