#pragma once
// Image resampling for loading datasets at a lower resolution.
#include "splat/core/image.hpp"

namespace splat {

// Resamples `image` to new_width x new_height with an area (box) filter: each output pixel
// is the average of the input over the rectangle it covers when both images span the same
// extent, partly covered input pixels weighted by their covered fraction. An integer factor
// K = W / new_width averages K x K blocks. Because the whole extent maps onto the whole
// extent, intrinsics scale exactly by new/old size (Camera::resized). Any channel count;
// parallel over rows, deterministic. Throws ArgumentError for a non-positive size or an
// inconsistent image.
Image resample_area(const Image& image, int new_width, int new_height);

}  // namespace splat
