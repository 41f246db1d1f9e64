#pragma once
// Turning a model half a turn about its x axis: (x, y, z) → (x, −y, −z). This is the change
// between the two world conventions splat files use, "right, down, forward" (the 3DGS PLY,
// COLMAP, OpenCV) and "right, up, back" (OpenGL, three.js, .spz): a proper rotation, so
// every Gaussian keeps its shape and its colours keep following the view direction.
#include "splat/gaussians/gaussian_model.hpp"

namespace splat {

// Rotates every mean, every Gaussian's orientation (q → (w, x, −y, −z)) and every
// spherical-harmonic coefficient (each basis function is even or odd under the turn), so
// that the model seen from the turned camera is the same image. Its own inverse.
void turn_half_about_x(GaussianModel& model);

}  // namespace splat
